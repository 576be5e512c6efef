#include "SurfaceGeometry.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <vector>

namespace bop::shape {
namespace {

// Sampled 1-D kernels on [-R, R]: smoothing G, first derivative D and second derivative DD,
// normalised so that they are exact on constants, ramps and parabolas respectively.
struct Kernels {
    int radius = 0;
    std::vector<double> g, d, dd;

    explicit Kernels(double sigma) {
        radius = int(std::ceil(3.0 * sigma));
        const int w = 2 * radius + 1;
        g.resize(w);
        d.resize(w);
        dd.resize(w);
        double sg = 0, sd = 0, s0 = 0, s2 = 0, s4 = 0;
        for (int t = -radius; t <= radius; ++t) {
            const double e = std::exp(-0.5 * t * t / (sigma * sigma));
            g[t + radius] = e;
            sg += e;
        }
        for (int t = -radius; t <= radius; ++t) {
            double& e = g[t + radius];
            e /= sg;
            d[t + radius] = t * e;
            sd += t * t * e;  // sum of t * D(t) must be 1
            s0 += e;
            s2 += t * t * e;
            s4 += double(t) * t * t * t * e;
        }
        for (auto& x : d) x /= sd;
        // DD(t) = a t^2 g + b g with sum DD = 0 and sum (t^2 / 2) DD = 1.
        const double det = s4 * s0 - s2 * s2;
        const double a = 2 * s0 / det, b = -2 * s2 / det;
        for (int t = -radius; t <= radius; ++t) dd[t + radius] = (a * t * t + b) * g[t + radius];
    }
};

struct Derivatives {
    double fx, fy, fz, fxx, fyy, fzz, fxy, fxz, fyz;
};

// Gaussian derivatives of chi(u) = [u outside bag `level`] at voxel (i, j, k); outside the grid
// chi = 1. Separable: reduce along x, then y, then z.
Derivatives derivativesAt(const BagLayout& bags, int level, int i, int j, int k, const Kernels& K,
                          std::vector<double>& scratch) {
    const int R = K.radius, W = 2 * R + 1;
    scratch.assign(std::size_t(3) * W * W + std::size_t(6) * W, 0.0);
    double* xg = scratch.data();  // [z][y] after x reduction with G, D, DD
    double* xd = xg + W * W;
    double* xdd = xd + W * W;
    double* yz = xdd + W * W;  // 6 combos [c][z]
    const Dims& dm = bags.bag.dims;
    for (int c = -R; c <= R; ++c)
        for (int b = -R; b <= R; ++b) {
            double sg = 0, sd = 0, sdd = 0;
            const int y = j + b, z = k + c;
            const bool rowIn = y >= 0 && z >= 0 && y < dm.ny && z < dm.nz;
            for (int a = -R; a <= R; ++a) {
                const int x = i + a;
                const bool in = rowIn && x >= 0 && x < dm.nx;
                const double chi = (!in || !bags.within(bags.bag(x, y, z), level)) ? 1.0 : 0.0;
                if (chi == 0.0) continue;
                sg += K.g[a + R];
                sd += K.d[a + R];
                sdd += K.dd[a + R];
            }
            const int o = (c + R) * W + (b + R);
            xg[o] = sg;
            xd[o] = sd;
            xdd[o] = sdd;
        }
    // combos along y: 0 GG, 1 DG (x-deriv), 2 GD, 3 DDG, 4 GDD, 5 DD
    for (int c = 0; c < W; ++c) {
        double v[6] = {0, 0, 0, 0, 0, 0};
        for (int b = 0; b < W; ++b) {
            const int o = c * W + b;
            v[0] += xg[o] * K.g[b];
            v[1] += xd[o] * K.g[b];
            v[2] += xg[o] * K.d[b];
            v[3] += xdd[o] * K.g[b];
            v[4] += xg[o] * K.dd[b];
            v[5] += xd[o] * K.d[b];
        }
        for (int m = 0; m < 6; ++m) yz[m * W + c] = v[m];
    }
    Derivatives r{};
    for (int c = 0; c < W; ++c) {
        const double* col = yz;
        r.fx += col[1 * W + c] * K.g[c];
        r.fy += col[2 * W + c] * K.g[c];
        r.fz += col[0 * W + c] * K.d[c];
        r.fxx += col[3 * W + c] * K.g[c];
        r.fyy += col[4 * W + c] * K.g[c];
        r.fzz += col[0 * W + c] * K.dd[c];
        r.fxy += col[5 * W + c] * K.g[c];
        r.fxz += col[1 * W + c] * K.d[c];
        r.fyz += col[2 * W + c] * K.d[c];
    }
    return r;
}

// Fallback normal where the smoothed gradient vanishes: mean direction to "outside" neighbours.
Eigen::Vector3f faceNormal(const BagLayout& bags, int level, int i, int j, int k) {
    static constexpr int kOff[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    for (const auto& o : kOff) {
        const int a = i + o[0], b = j + o[1], c = k + o[2];
        if (!bags.bag.dims.contains(a, b, c) || !bags.within(bags.bag(a, b, c), level))
            n += Eigen::Vector3f(o[0], o[1], o[2]);
    }
    return n.norm() > 0 ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f(0, 0, 1);
}

}  // namespace

float cpWeight(double kappa, double r0Voxels, const SurfaceGeometryParams& p) {
    const double x = p.cpWeightC * kappa * r0Voxels;
    return float(p.cpWeightForm == CpWeightForm::Linear ? 1.0 / (1.0 + x) : 1.0 / (1.0 + x * x));
}

void computeSurfaceGeometry(const BagLayout& bags, const SurfaceGeometryParams& p, GradientMap& map) {
    const Kernels K(p.sigmaVoxels);
    const long long n = (long long)map.surface.size();
#pragma omp parallel
    {
        std::vector<double> scratch;
#pragma omp for schedule(dynamic, 256)
        for (long long s = 0; s < n; ++s) {
            SurfaceVoxel& sv = map.surface[std::size_t(s)];
            const Eigen::Vector3i c = map.dims().coords(sv.voxel);
            const int level = bagOfSpecies(sv.species);  // bag of this surface
            const Derivatives f = derivativesAt(bags, level, c.x(), c.y(), c.z(), K, scratch);
            const Eigen::Vector3d g(f.fx, f.fy, f.fz);
            const double g2 = g.squaredNorm();
            if (g2 < 1e-12) {
                sv.normal = faceNormal(bags, level, c.x(), c.y(), c.z());
                sv.meanCurvature = sv.gaussCurvature = sv.kappa = 0;
            } else {
                sv.normal = g.normalized().cast<float>();
                const double gn = std::sqrt(g2);
                const double H =
                    (f.fx * f.fx * (f.fyy + f.fzz) + f.fy * f.fy * (f.fxx + f.fzz) + f.fz * f.fz * (f.fxx + f.fyy) -
                     2 * f.fx * f.fy * f.fxy - 2 * f.fx * f.fz * f.fxz - 2 * f.fy * f.fz * f.fyz) /
                    (2 * g2 * gn);
                const double K2 =
                    (f.fx * f.fx * (f.fyy * f.fzz - f.fyz * f.fyz) + f.fy * f.fy * (f.fxx * f.fzz - f.fxz * f.fxz) +
                     f.fz * f.fz * (f.fxx * f.fyy - f.fxy * f.fxy) + 2 * f.fy * f.fz * (f.fxy * f.fxz - f.fxx * f.fyz) +
                     2 * f.fx * f.fz * (f.fxy * f.fyz - f.fyy * f.fxz) +
                     2 * f.fx * f.fy * (f.fxz * f.fyz - f.fzz * f.fxy)) /
                    (g2 * g2);
                sv.meanCurvature = float(H);
                sv.gaussCurvature = float(K2);
                sv.kappa = float(std::sqrt(std::max(2 * H * H - K2, 0.0)));
            }
            sv.cpWeight = cpWeight(sv.kappa, map.r0Voxels, p);
        }
    }
}

}  // namespace bop::shape
