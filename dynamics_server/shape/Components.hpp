#pragma once
// Connected pieces of a voxel set. Face neighbours (6-connectivity) by default: the connectivity
// in which the surface shell of docs/shape-pipeline.md separates inside from outside. A shell one
// voxel thick is a piece in 26-connectivity (faces, edges and corners), which may step diagonally.
#include "bop/common/Volume.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace bop::shape {

struct Components {
    std::vector<std::uint32_t> label;  // per voxel: piece number from 1 (largest first), 0 = not in the set
    std::vector<std::size_t> sizes;    // voxels of piece p at sizes[p - 1], largest first
};

enum class Neighbours { Faces, All };  // 6 or 26 neighbours of a voxel

// The pieces of {v : in(v)} on a grid of `dims`; ties in size keep the order of first voxel.
Components findComponents(const Dims& dims, const std::function<bool(std::size_t)>& in,
                          Neighbours neighbours = Neighbours::Faces);

}  // namespace bop::shape
