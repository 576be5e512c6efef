// Windows read straight from the gradient-map cache file equal the in-memory crop of the whole
// map, answer every query as the whole map does, and read only about their share of the file.
#include "ShapeTestUtil.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "shape/GradientMapFileView.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace bop;
using namespace bop::shape;

namespace {

const Dims kDims{20, 18, 16};

// Frame 0: one sphere; frame 1: two nested bags around another centre, so the frames differ.
std::vector<GradientMap> twoFrames() {
    using P = Eigen::Vector3d;
    return {test::mapFrom(test::depthFrom(kDims, {[](const P& x) { return (x - P(10, 9, 8)).norm() < 6; }})),
            test::mapFrom(test::depthFrom(kDims, {[](const P& x) { return (x - P(9, 8, 7)).norm() < 7; },
                                                  [](const P& x) { return (x - P(9, 8, 7)).norm() < 3.5; }}))};
}

VoxelWindow window(int x0, int y0, int z0, int x1, int y1, int z1) {
    return {{x0, y0, z0}, {x1, y1, z1}};
}

void requireSameHeader(const GradientMap& a, const GradientMap& b) {
    CHECK(a.dims() == b.dims());
    CHECK(a.grid.originMm == b.grid.originMm);
    CHECK(a.grid.voxelMm == b.grid.voxelMm);
    CHECK(a.r0Voxels == b.r0Voxels);
    CHECK(a.bagCount == b.bagCount);
    CHECK(a.origin == b.origin);
    CHECK(a.whole == b.whole);
}

void requireSameMap(const GradientMap& a, const GradientMap& b) {
    requireSameHeader(a, b);
    CHECK(a.occ == b.occ);
    CHECK(a.nearest == b.nearest);
    REQUIRE(a.surface.size() == b.surface.size());
    for (std::size_t s = 0; s < a.surface.size(); ++s) {
        const SurfaceVoxel &x = a.surface[s], &y = b.surface[s];
        CHECK(x.voxel == y.voxel);
        CHECK(x.species == y.species);
        CHECK(x.normal == y.normal);
        CHECK(x.meanCurvature == y.meanCurvature);
        CHECK(x.gaussCurvature == y.gaussCurvature);
        CHECK(x.kappa == y.kappa);
        CHECK(x.cpWeight == y.cpWeight);
    }
}

}  // namespace

TEST_CASE("gradient-map file view crops equal in-memory crops", "[shape][cache][crop]") {
    const std::vector<GradientMap> frames = twoFrames();
    REQUIRE(frames[1].bagCount == 2);
    test::TempDir dir("gmview");
    const std::string path = dir.file("map.bopgm");
    writeGradientMaps(path, frames, 42);
    const auto view = GradientMapFileView::open(path, 42);
    REQUIRE(view);
    REQUIRE(view->frames() == 2);
    const auto fileBytes = std::filesystem::file_size(path);

    const std::vector<VoxelWindow> windows = {
        window(0, 0, 0, 20, 18, 16),    // the whole map
        window(0, 0, 0, 5, 4, 3),       // a corner
        window(0, 0, 6, 20, 18, 9),     // a z slab (contiguous in the file)
        window(3, 5, 0, 17, 9, 16),     // a y slab
        window(10, 9, 8, 11, 10, 9),    // a single voxel
        window(13, 11, 9, 20, 18, 16),  // touching the far faces
    };
    for (int f = 0; f < 2; ++f) {
        const GradientMap& whole = frames[std::size_t(f)];
        const GradientMap h = view->header(f);
        requireSameHeader(h, whole);
        CHECK(h.occ.empty());
        CHECK(h.nearest.empty());
        CHECK(h.surface.empty());
        for (const VoxelWindow& w : windows) {
            INFO("frame " << f << ", window " << w.lo.transpose() << " to " << w.hi.transpose());
            std::uint64_t bytesRead = 0;
            const GradientMap c = view->crop(f, w, &bytesRead);
            requireSameMap(c, cropGradientMap(whole, w));
            CHECK(c.origin == w.lo);
            CHECK(c.whole == kDims);
            CHECK(bytesRead <= fileBytes);
            // Every voxel of the crop answers as the whole map does at the same place.
            for (std::size_t v = 0; v < c.occ.size(); ++v) {
                const std::size_t u = c.wholeIndex(v);
                REQUIRE(c.voxelAt(c.wholeCoords(v)) == v);
                REQUIRE(c.occ[v] == whole.occ[u]);
                REQUIRE(c.delta(v) == whole.delta(u));
                REQUIRE(c.nearestSpecies(v) == whole.nearestSpecies(u));
                REQUIRE(c.signedDistance(v) == whole.signedDistance(u));
            }
        }
    }

    // A small window holds, and reads, a small part of the map and the file.
    std::uint64_t bytesRead = 0;
    const GradientMap corner = view->crop(1, windows[1], &bytesRead);
    INFO("corner 5x4x3 of frame 1: " << bytesRead << " bytes read of a " << fileBytes << "-byte file");
    CHECK(gradientMapBytes(corner) < gradientMapBytes(frames[1]) / 4);
    CHECK(bytesRead < fileBytes / 20);

    CHECK_THROWS_AS(view->crop(0, window(0, 0, 0, 21, 18, 16), nullptr), std::invalid_argument);
    CHECK_THROWS_AS(view->crop(2, windows[0], nullptr), std::out_of_range);
}

TEST_CASE("gradient-map file view tells stale, absent, corrupt and truncated files apart", "[shape][cache]") {
    const std::vector<GradientMap> frames = twoFrames();
    test::TempDir dir("gmview");
    const std::string path = dir.file("map.bopgm");
    writeGradientMaps(path, frames, 42);
    CHECK_FALSE(GradientMapFileView::open(path, 43));                      // another scene: stale
    CHECK_FALSE(GradientMapFileView::open(dir.file("absent.bopgm"), 42));  // nothing cached yet

    const auto view = GradientMapFileView::open(path, 42);
    REQUIRE(view);
    writeGradientMaps(path, {frames[0]}, 42);  // replaced after open: the view notices
    CHECK_THROWS_WITH(view->crop(0, window(0, 0, 0, 2, 2, 2)), Catch::Contains(path) && Catch::Contains("changed"));

    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(200);
        f.put('\x7f');
    }
    CHECK_THROWS_WITH(GradientMapFileView::open(path, 42), Catch::Contains(path) && Catch::Contains("corrupt"));

    writeGradientMaps(path, frames, 42);
    std::filesystem::resize_file(path, std::filesystem::file_size(path) - 100);
    CHECK_THROWS_WITH(GradientMapFileView::open(path, 42), Catch::Contains(path) && Catch::Contains("checksum"));
    std::filesystem::resize_file(path, 10);
    CHECK_THROWS_WITH(GradientMapFileView::open(path, 42), Catch::Contains(path) && Catch::Contains("truncated"));
    std::ofstream(path) << "hello";
    CHECK_THROWS_WITH(GradientMapFileView::open(path, 42), Catch::Contains("not a BoP gradient-map file"));
}

TEST_CASE("gradient-map file view checks the records a window reads", "[shape][cache]") {
    // Files with a valid checksum but bad contents (a faulty writer): only windows that read the
    // bad entry fail.
    GradientMap m = twoFrames()[0];
    test::TempDir dir("gmview");
    const std::string path = dir.file("map.bopgm");
    const VoxelWindow first = window(0, 0, 0, 2, 2, 2), last = window(18, 16, 14, 20, 18, 16);

    GradientMap badNearest = m;
    badNearest.nearest[0] = std::uint32_t(m.surface.size());
    writeGradientMaps(path, {badNearest}, 7);
    auto view = GradientMapFileView::open(path, 7);
    REQUIRE(view);
    CHECK_THROWS_WITH(view->crop(0, first), Catch::Contains(path) && Catch::Contains("nearest-surface index"));
    CHECK_NOTHROW(view->crop(0, last));

    GradientMap badSpecies = m;
    const std::uint32_t named = m.nearest.back();  // the record the last voxel names
    badSpecies.surface[named].species = 2;         // even: a volume species
    writeGradientMaps(path, {badSpecies}, 7);
    view = GradientMapFileView::open(path, 7);
    REQUIRE(view);
    CHECK_THROWS_WITH(view->crop(0, last), Catch::Contains(path) && Catch::Contains("inconsistent surface record"));
}

TEST_CASE("windowAround maps a region and margin to voxels and clips at the faces", "[shape][crop]") {
    const double h = 0.5;  // simulation length units per voxel
    const VoxelWindow inner = windowAround(kDims, h, {2, 2, 2}, {3, 3.2, 3}, 1);
    CHECK(inner.lo == Eigen::Vector3i(2, 2, 2));  // floor((2 - 1) / 0.5)
    CHECK(inner.hi == Eigen::Vector3i(8, 9, 8));  // ceil((3 + 1) / 0.5), ceil(4.2 / 0.5)

    const VoxelWindow clipped = windowAround(kDims, h, {-5, 1, 7}, {1, 2, 100}, 0.5);
    CHECK(clipped.lo == Eigen::Vector3i(0, 1, 13));
    CHECK(clipped.hi == Eigen::Vector3i(3, 5, 16));

    // A region wholly past the far face still gets the last voxel, one wide.
    const VoxelWindow beyond = windowAround(kDims, h, {50, 0, 0}, {60, 20, 1e12}, 0);
    CHECK(beyond.lo == Eigen::Vector3i(19, 0, 0));
    CHECK(beyond.hi == Eigen::Vector3i(20, 18, 16));
    CHECK(beyond.dims().count() == 1 * 18 * 16);
}
