#pragma once
// Normals and curvature of a surface voxel from Gaussian-derivative filters of the smoothed
// "outside" indicator (Thirion & Gourdon; docs/physics.md §4.4, §5), and the co-planar weight
// derived from the curvature (§5.3). Written once for the shape pipeline (every surface voxel of a
// new map, shape/SurfaceGeometry) and the map edits of cutting (GradientMapEdit, a window's).
#include "GradientMap.hpp"

#include <Eigen/Core>

#include <cmath>
#include <vector>

namespace bop {

enum class CpWeightForm { Linear, Quadratic };  // w = 1/(1 + c k r0)  or  1/(1 + (c k r0)^2)

struct SurfaceGeometryParams {
    double sigmaVoxels = 2.0;  // Gaussian width of the smoothing, voxels (>= 1.5 recommended)
    double cpWeightC = 4.0;    // c in the co-planar weight, dimensionless
    CpWeightForm cpWeightForm = CpWeightForm::Linear;
};

// The co-planar weight for a curvature kappa (1/voxel) and r0 (voxels).
float cpWeight(double kappa, double r0Voxels, const SurfaceGeometryParams& p);

// Sampled 1-D kernels on [-R, R], R = ceil(3 sigma): smoothing G, first derivative D and second
// derivative DD, normalised so that they are exact on constants, ramps and parabolas.
struct SurfaceKernels {
    int radius = 0;
    std::vector<double> g, d, dd;
    explicit SurfaceKernels(double sigma);
};

// Gaussian derivatives of the indicator at a voxel: gradient and Hessian.
struct IndicatorDerivatives {
    double fx = 0, fy = 0, fz = 0, fxx = 0, fyy = 0, fzz = 0, fxy = 0, fxz = 0, fyz = 0;
};

// The derivatives of chi at voxel (i, j, k), chi(x, y, z) = outside(x, y, z) ? 1 : 0 (the caller
// answers for voxels beyond its grid). Separable: reduce along x, then y, then z.
template <class Outside>
IndicatorDerivatives indicatorDerivatives(const Outside& outside, int i, int j, int k, const SurfaceKernels& K,
                                          std::vector<double>& scratch);

// Sets sv's normal, curvatures and co-planar weight from the derivatives f; where the smoothed
// gradient vanishes the normal is `fallback` (the mean direction to outside face neighbours).
void setSurfaceGeometry(SurfaceVoxel& sv, const IndicatorDerivatives& f, const Eigen::Vector3f& fallback,
                        double r0Voxels, const SurfaceGeometryParams& p);

// The mean direction to voxel (i, j, k)'s outside face neighbours ((0, 0, 1) if none).
template <class Outside>
Eigen::Vector3f faceNormal(const Outside& outside, int i, int j, int k) {
    static constexpr int kOff[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    for (const auto& o : kOff)
        if (outside(i + o[0], j + o[1], k + o[2])) n += Eigen::Vector3f(float(o[0]), float(o[1]), float(o[2]));
    return n.norm() > 0 ? Eigen::Vector3f(n.normalized()) : Eigen::Vector3f(0, 0, 1);
}

template <class Outside>
IndicatorDerivatives indicatorDerivatives(const Outside& outside, int i, int j, int k, const SurfaceKernels& K,
                                          std::vector<double>& scratch) {
    const int R = K.radius, W = 2 * R + 1;
    scratch.assign(std::size_t(3) * W * W + std::size_t(6) * W, 0.0);
    double* xg = scratch.data();  // [z][y] after the x reduction with G, D, DD
    double* xd = xg + W * W;
    double* xdd = xd + W * W;
    double* yz = xdd + W * W;  // 6 combinations [c][z]
    for (int c = -R; c <= R; ++c)
        for (int b = -R; b <= R; ++b) {
            double sg = 0, sd = 0, sdd = 0;
            for (int a = -R; a <= R; ++a) {
                if (!outside(i + a, j + b, k + c)) continue;
                sg += K.g[std::size_t(a + R)];
                sd += K.d[std::size_t(a + R)];
                sdd += K.dd[std::size_t(a + R)];
            }
            const int o = (c + R) * W + (b + R);
            xg[o] = sg;
            xd[o] = sd;
            xdd[o] = sdd;
        }
    // combinations along y: 0 GG, 1 DG (x derivative), 2 GD, 3 DDG, 4 GDD, 5 DD
    for (int c = 0; c < W; ++c) {
        double v[6] = {0, 0, 0, 0, 0, 0};
        for (int b = 0; b < W; ++b) {
            const int o = c * W + b;
            v[0] += xg[o] * K.g[std::size_t(b)];
            v[1] += xd[o] * K.g[std::size_t(b)];
            v[2] += xg[o] * K.d[std::size_t(b)];
            v[3] += xdd[o] * K.g[std::size_t(b)];
            v[4] += xg[o] * K.dd[std::size_t(b)];
            v[5] += xd[o] * K.d[std::size_t(b)];
        }
        for (int m = 0; m < 6; ++m) yz[m * W + c] = v[m];
    }
    IndicatorDerivatives r;
    for (int c = 0; c < W; ++c) {
        const double g = K.g[std::size_t(c)], d = K.d[std::size_t(c)], dd = K.dd[std::size_t(c)];
        r.fx += yz[1 * W + c] * g;
        r.fy += yz[2 * W + c] * g;
        r.fz += yz[0 * W + c] * d;
        r.fxx += yz[3 * W + c] * g;
        r.fyy += yz[4 * W + c] * g;
        r.fzz += yz[0 * W + c] * dd;
        r.fxy += yz[5 * W + c] * g;
        r.fxz += yz[1 * W + c] * d;
        r.fyz += yz[2 * W + c] * d;
    }
    return r;
}

}  // namespace bop
