#pragma once
// Cutting a gradient map while the bag runs (docs/shape-pipeline.md, "Map edits"): the voxels a
// blade sweeps leave every bag; the labels, the exact distance map (each voxel's nearest surface
// voxel), the normals, curvatures and co-planar weights are recomputed in a window around the
// cut, and the result is a patch that any copy of the map (the whole map, a rank's window, the
// haptic client's copy) takes with applyPatch. The patch equals a whole-grid rebuild of the edited
// image: distances exactly, records to the last bit.
#include "GradientMap.hpp"
#include "GradientMapCrop.hpp"
#include "SurfaceFilters.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace bop {

// The volume a blade sweeps: every point within `radius` of the segment a-b. Whole-map voxel
// coordinates (voxel i spans [i, i + 1), its centre at i + 0.5); a point blade has a == b.
struct BladeSweep {
    Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
    double radius = 0;  // voxels
    bool holds(const Eigen::Vector3d& x) const;
};

struct MapPatch {
    VoxelWindow window;                  // the voxels it rewrites, whole-map coordinates (empty: no change)
    std::vector<std::uint8_t> occ;       // per voxel of the window (x fastest), the new species
    std::vector<std::uint32_t> nearest;  // per voxel of the window, whole-map index of its nearest surface voxel
    // Sorted by voxel: every surface record the window names and every record the edit recomputed
    // (the surface voxels within the smoothing's reach of a changed voxel).
    std::vector<SurfaceVoxel> records;
    std::size_t removed = 0, newSurface = 0;  // voxels the blade took out; volume voxels that became surface
    std::vector<int> bags;                    // the bags that lost voxels, in increasing order
    int grows = 0;                            // times the window was widened to hold every changed voxel
    bool empty() const { return occ.empty(); }
};

// Whether a voxel (whole-map coordinates) leaves its bag.
using VoxelPredicate = std::function<bool(const Eigen::Vector3i&)>;

// Reads a window of the current map (records named by its voxels included, as a crop).
using MapWindowReader = std::function<GradientMap(const VoxelWindow&)>;

// The patch of sweeping `blade` through the map `read` gives (whole dims `whole`, r0 in voxels);
// p: the map's surface-geometry parameters. Empty when the blade meets no voxel of any bag;
// std::domain_error when it would take every voxel of every bag. One thread; deterministic.
MapPatch cutPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels, const BladeSweep& blade,
                  const SurfaceGeometryParams& p);

// The same for any voxels: those of `box` (whole-map coordinates, within the grid) that `takes`
// leave their bags (a dent that yields, core/Plasticity.hpp).
MapPatch removalPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels, const VoxelWindow& box,
                      const VoxelPredicate& takes, const SurfaceGeometryParams& p);

// The same for a list of voxels (whole-map linear indices, x fastest, increasing), over the box
// that holds them; std::invalid_argument when they are out of order or beyond the grid
// (common/src/VoxelRemoval.cpp).
MapPatch voxelsPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels,
                     const std::vector<std::uint64_t>& voxels, const SurfaceGeometryParams& p);
// The box of a set of voxels (whole-map linear indices) in a grid of dims `whole`; empty for none.
VoxelWindow boxOfVoxels(const std::vector<std::uint64_t>& voxels, const Dims& whole);

// `map` (a whole map or a window of one) with the patch applied: its voxels inside the patch's
// window rewritten, every record the patch holds replacing the map's. Linear in map's size.
GradientMap applyPatch(const GradientMap& map, const MapPatch& patch);

}  // namespace bop
