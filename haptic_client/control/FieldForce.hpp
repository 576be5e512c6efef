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

#include <atomic>
#include <memory>

namespace bop::haptic {

// The map can be replaced while the loop reads it (a cut, FieldCutter): each query reads one map
// whole, the one in force when it began.
class FieldForce {
public:
    FieldForce(GradientMap map, double stiffness);  // stiffness: force / length
    FieldForce(const FieldForce& other);
    FieldForce& operator=(const FieldForce&) = delete;

    std::shared_ptr<const GradientMap> map() const { return map_.load(); }
    void setMap(std::shared_ptr<const GradientMap> map) { map_.store(std::move(map)); }

    double signedDistance(const Eigen::Vector3d& x) const;   // length; > 0 outside every bag
    Eigen::Vector3d normal(const Eigen::Vector3d& x) const;  // outward, of the nearest surface
    Eigen::Vector3d operator()(const Eigen::Vector3d& x) const;
    double voxelSize() const { return h_; }  // length
    // The centre of the highest surface voxel (largest z; the first of equals), length: where a
    // poke from above meets the bag.
    Eigen::Vector3d top() const;

private:
    // Distance and its gradient; a voxel's distance, length, clamped into the grid.
    double sample(const GradientMap& m, const Eigen::Vector3d& x, Eigen::Vector3d* gradient) const;
    double distanceAtVoxel(const GradientMap& m, int i, int j, int k) const;
    Eigen::Vector3d normal(const GradientMap& m, const Eigen::Vector3d& x) const;
    std::atomic<std::shared_ptr<const GradientMap>> map_;
    double stiffness_, h_;
};

}  // namespace bop::haptic
