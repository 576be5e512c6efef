#pragma once
// Parts of a bag too thin for it to hold (docs/shape-pipeline.md, "Thin parts"): the local
// thickness of the bag's voxels, from the exact distance transform to the voxels outside it.
// A ridge voxel (no neighbour of its 26 lies deeper) at depth d (voxels, to the nearest voxel
// outside) marks a part 2d - 1 voxels across (a plate t voxels thick has its middle at depth
// (t + 1) / 2); the ball of radius d around it is that part. A part under `minimum` voxels across
// cannot hold the bag's two sheets of surface particles and a volume between them.
#include "bop/common/GradientMap.hpp"

#include <string>
#include <vector>

namespace bop::shape {

struct ThinParts {
    double thinnestVoxels = 0;   // the thinnest part across, voxels (0: the bag has no voxels)
    std::size_t thinVoxels = 0;  // the bag's voxels inside parts under the minimum
    std::size_t bagVoxels = 0;   // every voxel of the bag (its surface, volume and the bags inside it)
};

// Bag number `bag` (1 = outermost) of the whole map `map`; `minimumVoxels` across. With `mask`
// (sized to the map's voxels), its voxels in thin parts are set to 1.
ThinParts findThinParts(const GradientMap& map, int bag, double minimumVoxels, std::vector<char>* mask = nullptr);

// A warning for a bag with thin parts ("" when it has none), in r0 and voxels: the share of its
// voxels in them, the thinnest, and the r0_voxels that would hold it (two r0 across).
std::string thinPartsWarning(const std::string& bagName, const ThinParts& t, double r0Voxels);

// The warnings of every bag of the whole map `map` (bag k + 1 named bagNames[k]) that has parts
// under 2 r0 across, as bop-shape and bop-server print them before a bag is built.
// With `membrane` (resized to the map's voxels), every bag's voxels in those parts are set to 1:
// where a bag is a membrane, one sheet thick (app::PlacementParams::membrane).
std::vector<std::string> thinPartsWarnings(const GradientMap& map, const std::vector<std::string>& bagNames,
                                           std::vector<char>* membrane = nullptr);

}  // namespace bop::shape
