#pragma once
// A scene of a shape given by a predicate on voxel centres: the torus scene's settings with its
// mesh swapped for a raw image of the shape (1 mm voxels). Shared by the physics tests of
// shapes with thin parts, several pieces and cuts.
#include "TestUtil.hpp"

#include <Eigen/Core>

#include <functional>
#include <string>

namespace bop::test {

struct Shape {
    const char* name;
    Eigen::Vector3i size;                                // voxels of 1 mm
    std::function<bool(const Eigen::Vector3d&)> inside;  // at a voxel centre, voxel units
    double area;                                         // analytic, voxel^2
    std::function<int(const Eigen::Vector3d&)> piece;    // which piece a point belongs to (0, 1, ...)
};

// The scene file written in `dir`: the torus scene's construction timeline kept (birth) or
// removed (the bag is placed), its [run] table left out.
std::string writeScene(const TempDir& dir, const Shape& s, bool birth = false);

}  // namespace bop::test
