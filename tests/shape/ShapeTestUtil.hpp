#pragma once
// Helpers shared by the shape tests: analytic volumes on a grid and maps built from them.
#include "TestUtil.hpp"
#include "core/Model.hpp"
#include "shape/ShapeBuilder.hpp"

#include <functional>
#include <string>

namespace bop::test {

// depth(v) = number of predicates (outer to inner) that hold at the voxel centre (voxel units).
Volume<std::uint8_t> depthFrom(const Dims& d, const std::vector<std::function<bool(const Eigen::Vector3d&)>>& inside);

// A gradient map built from a depth volume on a grid of 1 mm voxels at the origin.
GradientMap mapFrom(const Volume<std::uint8_t>& depth, double r0Voxels = 2.0, double sigma = 2.0);

// Two maps alike field by field (Catch REQUIREs): occupancy, the squared distance to each voxel's
// nearest surface voxel, and every surface record (voxel, species, normal, curvatures, co-planar
// weight) to the bit.
void requireSameMap(const GradientMap& edited, const GradientMap& truth);

// One bag on `map`: species 1 its surface, 2 its volume; the box is the map's.
core::Model bagModel(const GradientMap& map);

}  // namespace bop::test
