// The gradient-map cache: a round trip keeps every field; stale, truncated and corrupt files
// are told apart.
#include "ShapeTestUtil.hpp"
#include "bop/common/GradientMapFile.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

using namespace bop;
using namespace bop::shape;

TEST_CASE("gradient-map cache round trip and error cases", "[shape][cache]") {
    const Dims d{20, 18, 16};
    const GradientMap m = test::mapFrom(
        test::depthFrom(d, {[](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(10, 9, 8)).norm() < 6; }}));
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
    CHECK_FALSE(readGradientMaps(path, 43));                      // another scene: stale
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

TEST_CASE("the map file reads the same from its bytes in memory as from the file, and refuses damage by name",
          "[shape][cache]") {
    const GradientMap m = test::mapFrom(test::depthFrom(
        Dims{14, 12, 10}, {[](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(7, 6, 5)).norm() < 4; }}));
    test::TempDir dir("gmmemory");
    const std::string path = dir.file("map.bopgm");
    writeGradientMaps(path, {m}, 7);
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto fromFile = readGradientMaps(path, 7), fromMemory = readGradientMaps(bytes, 7, "the download");
    REQUIRE(fromFile);
    REQUIRE(fromMemory);
    CHECK(fromMemory->front().occ == fromFile->front().occ);
    CHECK(fromMemory->front().nearest == fromFile->front().nearest);
    CHECK(fromMemory->front().surface.size() == fromFile->front().surface.size());
    CHECK_FALSE(readGradientMaps(bytes, 8, "the download"));  // another scene's
    bytes[bytes.size() / 2] ^= 0x40;
    CHECK_THROWS_WITH(readGradientMaps(bytes, 7, "the download"),
                      Catch::Contains("the download") && Catch::Contains("corrupt"));
    bytes.resize(20);
    CHECK_THROWS_WITH(readGradientMaps(bytes, 7, "the download"), Catch::Contains("the download"));
}
