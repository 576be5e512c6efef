#include "control/FieldForce.hpp"

#include "bop/common/Units.hpp"

#include <algorithm>
#include <cmath>

namespace bop::haptic {

FieldForce::FieldForce(GradientMap map, double stiffness)
    : map_(std::make_shared<const GradientMap>(std::move(map))),
      stiffness_(stiffness),
      h_(voxelLength(map_.load()->r0Voxels)) {}

FieldForce::FieldForce(const FieldForce& other) : map_(other.map()), stiffness_(other.stiffness_), h_(other.h_) {}

double FieldForce::distanceAtVoxel(const GradientMap& m, int i, int j, int k) const {
    const Dims& d = m.dims();
    i = std::clamp(i, 0, d.nx - 1), j = std::clamp(j, 0, d.ny - 1), k = std::clamp(k, 0, d.nz - 1);
    const std::size_t v = d.index(i, j, k);
    // Inside any bag (occ > 0) counts as inside: the probe is pushed out of the outer surface.
    const double dist = m.delta(v).cast<double>().norm() * h_;
    return m.occ[v] > 0 ? -dist : dist;
}

double FieldForce::sample(const GradientMap& m, const Eigen::Vector3d& x, Eigen::Vector3d* gradient) const {
    const Eigen::Vector3d p = x / h_ - Eigen::Vector3d::Constant(0.5);  // voxel centres at integers
    const Eigen::Vector3d base = p.array().floor();
    const Eigen::Vector3d f = p - base;
    const int i = int(base.x()), j = int(base.y()), k = int(base.z());
    double s = 0;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();  // d s / d p, per voxel
    for (int c = 0; c < 8; ++c) {
        const int a = c & 1, b = (c >> 1) & 1, e = (c >> 2) & 1;
        const double wx = a ? f.x() : 1 - f.x(), wy = b ? f.y() : 1 - f.y(), wz = e ? f.z() : 1 - f.z();
        const double d = distanceAtVoxel(m, i + a, j + b, k + e);
        s += wx * wy * wz * d;
        g += d * Eigen::Vector3d((a ? 1 : -1) * wy * wz, wx * (b ? 1 : -1) * wz, wx * wy * (e ? 1 : -1));
    }
    if (gradient) *gradient = g / h_;
    return s;
}

double FieldForce::signedDistance(const Eigen::Vector3d& x) const {
    return sample(*map(), x, nullptr);
}

Eigen::Vector3d FieldForce::normal(const Eigen::Vector3d& x) const {
    return normal(*map(), x);
}

Eigen::Vector3d FieldForce::normal(const GradientMap& m, const Eigen::Vector3d& x) const {
    const Dims& d = m.dims();
    const Eigen::Vector3i c = (x / h_).array().floor().cast<int>().matrix();
    const std::size_t v =
        d.index(std::clamp(c.x(), 0, d.nx - 1), std::clamp(c.y(), 0, d.ny - 1), std::clamp(c.z(), 0, d.nz - 1));
    return m.nearestSurface(v).normal.cast<double>();
}

Eigen::Vector3d FieldForce::top() const {
    Eigen::Vector3i best(0, 0, -1);
    const std::shared_ptr<const GradientMap> m = map();
    for (const SurfaceVoxel& s : m->surface) {
        const Eigen::Vector3i c = m->wholeDims().coords(s.voxel);
        if (c.z() > best.z()) best = c;
    }
    return (best.cast<double>() + Eigen::Vector3d::Constant(0.5)) * h_;
}

Eigen::Vector3d FieldForce::operator()(const Eigen::Vector3d& x) const {
    Eigen::Vector3d g;
    const std::shared_ptr<const GradientMap> m = map();
    const double s = sample(*m, x, &g);
    if (s >= 0) return Eigen::Vector3d::Zero();
    // Outward: the gradient of the interpolated distance, continuous like it; where it vanishes
    // (a ridge of the distance), the nearest surface's normal.
    const Eigen::Vector3d n = g.norm() > 1e-9 ? Eigen::Vector3d(g.normalized()) : normal(*m, x);
    return -stiffness_ * s * n;
}

}  // namespace bop::haptic
