#pragma once
// A rank's window of the gradient map: the voxels of its subdomain plus a margin, and only the
// surface voxels those voxels name, so that map memory per rank shrinks as ranks grow
// (docs/parallel.md). The crop answers every query inside it exactly as the whole map does.
#include "bop/common/GradientMap.hpp"

#include <Eigen/Core>

namespace bop {

// Voxels [lo, hi) of the whole map, in whole-map voxel coordinates.
struct VoxelWindow {
    Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = Eigen::Vector3i::Zero();
    Dims dims() const { return {hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()}; }
};

// The voxels that cover the region [regionLo, regionHi] (simulation length units) grown by
// margin (simulation length units) on every side, clipped to the whole map `whole`; voxels
// are h (simulation length units) wide. At least one voxel on each axis.
VoxelWindow windowAround(const Dims& whole, double h, const Eigen::Vector3d& regionLo, const Eigen::Vector3d& regionHi,
                         double margin);

// The part of `map` (a whole map, or a window of one holding `window`) inside `window`; surface
// voxels keep their whole-map index.
GradientMap cropGradientMap(const GradientMap& map, const VoxelWindow& window);

// Bytes the map's arrays hold (per-voxel occupancy and nearest index, surface records).
std::size_t gradientMapBytes(const GradientMap& map);

}  // namespace bop
