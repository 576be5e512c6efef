#pragma once
// Anti-aliased boundaries for bags from label images (docs/shape-pipeline.md, "Smooth
// boundaries"). A segmentation's labels are staircases: slices thicker than the grid's voxels,
// and a voxel's worth of noise. Each bag's signed distance to its own boundary (voxel centres,
// ±½ voxel at the boundary) is smoothed by a Gaussian of width sigma; a voxel changes side where
// the smoothed boundary lies more than kSmoothingMargin voxels beyond its centre. A level offset
// of at most ½ voxel, chosen per bag, keeps the bag's volume; a voxel changes side only when
// that keeps the topology of the bag (a simple point) and the layout of the bags: bags that
// touched still touch without overlapping, a bag inside another stays inside it.
#include "bop/common/Volume.hpp"

#include <cstddef>
#include <vector>

namespace bop::shape {

// A voxel changes side only where the smoothed boundary lies further than this beyond its
// centre, voxels: smooth shapes (a ball of radius 5 voxels and up) keep their labels exactly.
inline constexpr double kSmoothingMargin = 0.1;
// The level offset that keeps a bag's volume moves its boundary by at most this, voxels.
inline constexpr double kMaxLevelShift = 0.5;

// A bag whose volume the smoothing would change by more than this fraction, even with the level
// offset, is smoothed with a width kWidthStep times narrower, down to kMinWidth voxels, else left as it is.
inline constexpr double kVolumeTolerance = 0.01;
inline constexpr double kWidthStep = 0.75;
inline constexpr double kMinWidth = 0.5;

struct BoundarySmoothingReport {
    std::size_t voxelsBefore = 0, voxelsAfter = 0;  // the bag's voxels
    std::size_t removed = 0, added = 0;             // voxels that changed side
    std::size_t keptForTopology = 0;                // changes left out: not simple, or the layout
    double levelShiftVoxels = 0;                    // the volume-keeping offset, voxels
    double widthVoxels = 0;                         // the width used; 0 = none kept the volume
};

// Smooths masks[b] where sigmaVoxels[b] > 0 (Gaussian width, grid voxels); masks all share one
// grid. Returns one report per mask (zeros for masks left as they were).
std::vector<BoundarySmoothingReport> smoothBoundaries(std::vector<Mask>& masks, const std::vector<double>& sigmaVoxels,
                                                      int threads = 0);

}  // namespace bop::shape
