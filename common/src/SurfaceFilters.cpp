#include "bop/common/SurfaceFilters.hpp"

#include <algorithm>

namespace bop {

float cpWeight(double kappa, double r0Voxels, const SurfaceGeometryParams& p) {
    const double x = p.cpWeightC * kappa * r0Voxels;
    return float(p.cpWeightForm == CpWeightForm::Linear ? 1.0 / (1.0 + x) : 1.0 / (1.0 + x * x));
}

SurfaceKernels::SurfaceKernels(double sigma) {
    radius = int(std::ceil(3.0 * sigma));
    const std::size_t w = std::size_t(2 * radius + 1);
    g.resize(w);
    d.resize(w);
    dd.resize(w);
    double sg = 0, sd = 0, s0 = 0, s2 = 0, s4 = 0;
    for (int t = -radius; t <= radius; ++t) {
        const double e = std::exp(-0.5 * t * t / (sigma * sigma));
        g[std::size_t(t + radius)] = e;
        sg += e;
    }
    for (int t = -radius; t <= radius; ++t) {
        double& e = g[std::size_t(t + radius)];
        e /= sg;
        d[std::size_t(t + radius)] = t * e;
        sd += t * t * e;  // the sum of t D(t) must be 1
        s0 += e;
        s2 += t * t * e;
        s4 += double(t) * t * t * t * e;
    }
    for (auto& x : d) x /= sd;
    // DD(t) = a t^2 g + b g with sum DD = 0 and sum (t^2 / 2) DD = 1.
    const double det = s4 * s0 - s2 * s2;
    const double a = 2 * s0 / det, b = -2 * s2 / det;
    for (int t = -radius; t <= radius; ++t) dd[std::size_t(t + radius)] = (a * t * t + b) * g[std::size_t(t + radius)];
}

void setSurfaceGeometry(SurfaceVoxel& sv, const IndicatorDerivatives& f, const Eigen::Vector3f& fallback,
                        double r0Voxels, const SurfaceGeometryParams& p) {
    const Eigen::Vector3d g(f.fx, f.fy, f.fz);
    const double g2 = g.squaredNorm();
    if (g2 < 1e-12) {
        sv.normal = fallback;
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
             2 * f.fx * f.fz * (f.fxy * f.fyz - f.fyy * f.fxz) + 2 * f.fx * f.fy * (f.fxz * f.fyz - f.fzz * f.fxy)) /
            (g2 * g2);
        sv.meanCurvature = float(H);
        sv.gaussCurvature = float(K2);
        sv.kappa = float(std::sqrt(std::max(2 * H * H - K2, 0.0)));
    }
    sv.cpWeight = cpWeight(sv.kappa, r0Voxels, p);
}

}  // namespace bop
