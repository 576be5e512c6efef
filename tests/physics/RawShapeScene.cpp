#include "RawShapeScene.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <regex>
#include <vector>

namespace bop::test {

std::string writeScene(const TempDir& dir, const Shape& s, bool birth) {
    std::vector<std::uint8_t> voxels;
    for (int z = 0; z < s.size.z(); ++z)
        for (int y = 0; y < s.size.y(); ++y)
            for (int x = 0; x < s.size.x(); ++x) voxels.push_back(s.inside(Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5)));
    std::ofstream(dir.file(std::string(s.name) + ".raw"), std::ios::binary)
        .write(reinterpret_cast<const char*>(voxels.data()), std::streamsize(voxels.size()));
    std::ifstream in(sourceDir() + "/config/scenes/torus.toml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string source = "source = \"raw\"\nfile = \"" + std::string(s.name) + ".raw\"\nsize_voxels = [" +
                               std::to_string(s.size.x()) + ", " + std::to_string(s.size.y()) + ", " +
                               std::to_string(s.size.z()) + "]\ndtype = \"uint8\"\nspacing_mm = [1, 1, 1]\nlabel = 1\n";
    text = std::regex_replace(text, std::regex("source = \"mesh\"\nfile = [^\n]*\nscale_mm = [^\n]*\n"), source);
    text = std::regex_replace(text, std::regex("voxel_size_mm = 2.25"), "voxel_size_mm = 1.0");
    const std::size_t from = text.find("# Build the bag"), to = text.find("# Oriented-particle");
    REQUIRE((from != std::string::npos && to != std::string::npos));
    if (!birth) text.erase(from, to - from);
    text.erase(text.find("[run]"));
    return writeText(dir.file(std::string(s.name) + ".toml"), text);
}

}  // namespace bop::test
