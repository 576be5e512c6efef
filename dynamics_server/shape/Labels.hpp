#pragma once
// Outside / surface / inside labels with the paper's 6-connectivity rule (§3.3), extended to
// nested bags (§3.4, docs/physics.md §4.1): a voxel of bag k (k bags contain it) that shares a face
// with a voxel of fewer bags, or with the grid border, is a surface voxel of bag k.
#include "bop/common/Volume.hpp"

#include <cstdint>
#include <vector>

namespace bop::shape {

// depth(v) = number of nested bags that contain v (0 = outside all).
// Returns occ(v): 0 outside, 2k-1 on the surface of bag k, 2k inside bag k (innermost bag).
std::vector<std::uint8_t> labelVoxels(const Volume<std::uint8_t>& depth);

// True if some 6-neighbour of v (or the grid border) has depth below `level`.
bool touchesBelow(const Volume<std::uint8_t>& depth, int i, int j, int k, int level);

}  // namespace bop::shape
