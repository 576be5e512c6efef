#pragma once
// Outside / surface / inside labels with the paper's 6-connectivity rule (§3.3), extended to
// several bags (§3.4, docs/physics.md §4.1): a voxel of bag k (the innermost bag holding it) that
// shares a face with a voxel outside bag k, or with the grid border, is a surface voxel of bag k.
// Two bags that touch each get their own surface along the faces they share.
#include "BagLayout.hpp"

#include <cstdint>
#include <vector>

namespace bop::shape {

// occ(v): 0 outside every bag, 2k-1 on the surface of bag k, 2k inside bag k.
std::vector<std::uint8_t> labelVoxels(const BagLayout& bags);

}  // namespace bop::shape
