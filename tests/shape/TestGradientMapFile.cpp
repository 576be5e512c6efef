// The gradient-map cache: a round trip keeps every field; stale, truncated and corrupt files
// are told apart.
#include "ShapeTestUtil.hpp"
#include "shape/GradientMapFile.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace bop;
using namespace bop::shape;

TEST_CASE("gradient-map cache round trip and error cases", "[shape][cache]") {
    const Dims d{20, 18, 16};
    const GradientMap m = test::mapFrom(test::depthFrom(d, {[](const Eigen::Vector3d& x) {
        return (x - Eigen::Vector3d(10, 9, 8)).norm() < 6;
    }}));
    test::TempDir dir("gmcache");
    const std::string path = dir.file("map.bopgm");
    writeGradientMaps(path, {m, m}, 42);
    const auto back = readGradientMaps(path, 42);
    REQUIRE(back);
    REQUIRE(back->size() == 2);
    const GradientMap& r = back->at(1);
    CHECK(r.dims() == d);
    CHECK(r.occ == m.occ);
    CHECK(r.nearest == m.nearest);
    REQUIRE(r.surface.size() == m.surface.size());
    for (std::size_t s = 0; s < r.surface.size(); ++s) {
        CHECK(r.surface[s].voxel == m.surface[s].voxel);
        CHECK(r.surface[s].normal == m.surface[s].normal);
        CHECK(r.surface[s].cpWeight == m.surface[s].cpWeight);
    }
    CHECK_FALSE(readGradientMaps(path, 43));                     // another scene: stale
    CHECK_FALSE(readGradientMaps(dir.file("absent.bopgm"), 42));  // nothing cached yet

    const auto size = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, size - 100);
    CHECK_THROWS_WITH(readGradientMaps(path, 42), Catch::Contains(path) && Catch::Contains("checksum"));
    writeGradientMaps(path, {m}, 42);
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        f.put('\x7f');
    }
    CHECK_THROWS_WITH(readGradientMaps(path, 42), Catch::Contains("corrupt"));
    std::ofstream(path) << "hello";
    CHECK_THROWS_WITH(readGradientMaps(path, 42), Catch::Contains("not a BoP gradient-map file"));
}
