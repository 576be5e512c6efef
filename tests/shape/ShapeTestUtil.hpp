#pragma once
// Helpers shared by the shape tests: temporary folders, scene files written on the fly,
// analytic volumes on a grid.
#include "shape/ShapeBuilder.hpp"

#include <filesystem>
#include <functional>
#include <string>

namespace bop::test {

// A fresh folder under the system temp dir, removed when the object dies.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& tag);
    ~TempDir();
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// Writes text to a file and returns its path.
std::string writeText(const std::string& path, const std::string& text);

// The repository root (for config/ files).
std::string sourceDir();

// depth(v) = number of predicates (outer to inner) that hold at the voxel centre (voxel units).
Volume<std::uint8_t> depthFrom(const Dims& d, const std::vector<std::function<bool(const Eigen::Vector3d&)>>& inside);

// A gradient map built from a depth volume on a grid of 1 mm voxels at the origin.
GradientMap mapFrom(const Volume<std::uint8_t>& depth, double r0Voxels = 2.0, double sigma = 2.0);

}  // namespace bop::test
