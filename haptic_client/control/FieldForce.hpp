#pragma once
// The gradient map as a field of force vectors on the probe (paper §4.3): inside the bag a
// spring pushes the probe out, stiffness times depth, along the gradient of the depth; outside
// it is 0. The depth is the voxel centres' distances to the nearest surface voxel, negative
// inside any bag, interpolated trilinearly, so the force is continuous. (Between nested bags
// the depth is to the nearer surface; the torus and the ventricle have one bag.)
// Map placement as the server's (dynamics_server/core/MapField.hpp): the corner of voxel (0,0,0) at the origin,
// a voxel h = r0 / r0Voxels wide (r0 = sqrt 3).
#include "bop/common/GradientMap.hpp"

#include <Eigen/Core>

namespace bop::haptic {

class FieldForce {
public:
    FieldForce(GradientMap map, double stiffness);  // stiffness: force / length

    double signedDistance(const Eigen::Vector3d& x) const;   // length; > 0 outside every bag
    Eigen::Vector3d normal(const Eigen::Vector3d& x) const;  // outward, of the nearest surface
    Eigen::Vector3d operator()(const Eigen::Vector3d& x) const;
    double voxelSize() const { return h_; }  // length
    // The centre of the highest surface voxel (largest z; the first of equals), length: where a
    // poke from above meets the bag.
    Eigen::Vector3d top() const;

private:
    double sample(const Eigen::Vector3d& x, Eigen::Vector3d* gradient) const;  // distance and its gradient
    double distanceAtVoxel(int i, int j, int k) const;                         // length, clamped into the grid
    GradientMap map_;
    double stiffness_, h_;
};

}  // namespace bop::haptic
