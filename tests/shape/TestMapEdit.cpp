// Cutting the map (bop/common/GradientMapEdit.hpp): a blade's patch, computed in a window around
// the cut, equals a whole-grid rebuild of the edited image: labels and distances exactly, every
// surface record (normal, curvatures, co-planar weight) to the last bit; a rank's window takes the
// patch as the whole map does; cuts one after another; the window stays a window.
#include "ShapeTestUtil.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapEdit.hpp"
#include "shape/BagLayout.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace bop;
using Inside = std::function<bool(const Eigen::Vector3d&)>;

namespace {

const Dims kDims{56, 48, 28};

SurfaceGeometryParams params() {
    SurfaceGeometryParams p;
    p.sigmaVoxels = 1.5;
    return p;
}

// A torus (tube radius 6 voxels around a ring of 14 in the x-y plane) and, beside it, a ball
// holding a smaller ball: side by side and nested bags in one map.
shape::BagLayout layoutOf() {
    const Eigen::Vector3d c(20, 24, 14), b(46, 24, 14);
    shape::BagLayout l;
    l.bag = Volume<std::uint8_t>(kDims, 0);
    l.parent = {0, 0, 0, 2};
    for (std::size_t v = 0; v < kDims.count(); ++v) {
        const Eigen::Vector3d x = kDims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
        const double ring = std::hypot(x.x() - c.x(), x.y() - c.y()) - 14;
        if (std::hypot(ring, x.z() - c.z()) < 6) l.bag.data[v] = 1;
        if ((x - b).norm() < 8.5) l.bag.data[v] = (x - b).norm() < 4 ? 3 : 2;
    }
    return l;
}

GradientMap rebuild(const shape::BagLayout& l) {
    VoxelGrid g;
    g.dims = kDims;
    return shape::buildGradientMap(g, l, 2.0, params(), nullptr, 1);
}

MapPatch cut(const GradientMap& whole, const BladeSweep& blade) {
    return cutPatch([&](const VoxelWindow& w) { return cropGradientMap(whole, w); }, kDims, whole.r0Voxels, blade,
                    params());
}

void sweepOut(shape::BagLayout& l, const BladeSweep& blade) {
    for (std::size_t v = 0; v < kDims.count(); ++v)
        if (blade.holds(kDims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5))) l.bag.data[v] = 0;
}

}  // namespace

TEST_CASE("map edit: a blade's windowed patch equals a whole-grid rebuild of the edited image", "[mapedit]") {
    shape::BagLayout layout = layoutOf();
    const GradientMap original = rebuild(layout);
    std::mt19937 rng(52);
    std::uniform_real_distribution<double> ux(0, kDims.nx), uy(0, kDims.ny), uz(0, kDims.nz), ur(0.8, 4.0), ul(-12, 12);
    GradientMap edited = original;
    int cuts = 0, windowed = 0;
    for (int t = 0; t < 14; ++t) {
        BladeSweep blade;
        // Mostly starting in an object (the torus's ring, the ball), sometimes anywhere.
        const Eigen::Vector3d centres[3] = {{34, 24, 14}, {20, 10, 14}, {46, 24, 14}};
        blade.a = t % 4 == 3 ? Eigen::Vector3d(ux(rng), uy(rng), uz(rng))
                             : Eigen::Vector3d(centres[t % 3] + Eigen::Vector3d(ul(rng), ul(rng), ul(rng)) / 4);
        blade.b = blade.a + Eigen::Vector3d(ul(rng), ul(rng), 0.3 * ul(rng));
        blade.radius = ur(rng);
        const MapPatch patch = cut(edited, blade);
        sweepOut(layout, blade);
        const GradientMap truth = rebuild(layout);
        if (patch.empty()) {
            REQUIRE(truth.occ == edited.occ);  // the blade met nothing
            continue;
        }
        ++cuts;
        windowed += patch.window.dims().count() < kDims.count();
        // A rank's window takes the patch as the whole map does.
        const VoxelWindow w{{10, 5, 3}, {40, 40, 25}};
        const GradientMap windowAfter = applyPatch(cropGradientMap(edited, w), patch);
        edited = applyPatch(edited, patch);
        test::requireSameMap(edited, truth);
        const GradientMap cropAfter = cropGradientMap(edited, w);
        REQUIRE(windowAfter.occ == cropAfter.occ);
        REQUIRE(windowAfter.nearest == cropAfter.nearest);
        REQUIRE(windowAfter.surface.size() == cropAfter.surface.size());
        for (std::size_t s = 0; s < cropAfter.surface.size(); ++s) {
            REQUIRE(windowAfter.surface[s].voxel == cropAfter.surface[s].voxel);
            REQUIRE(windowAfter.surface[s].normal == cropAfter.surface[s].normal);
        }
    }
    CHECK(cuts >= 8);
    CHECK(windowed >= cuts / 2);
}

TEST_CASE("map edit: the torus cut across its tube; the cut faces are new surface with outward normals", "[mapedit]") {
    shape::BagLayout layout = layoutOf();
    const GradientMap original = rebuild(layout);
    BladeSweep blade;  // across the tube at the ring's +x side, a slab 3 voxels thick
    blade.a = {34, 24, 0};
    blade.b = {34, 24, 28};
    blade.radius = 1.5;
    const MapPatch patch = cut(original, blade);
    REQUIRE(patch.removed > 0);
    REQUIRE(patch.newSurface > 0);
    INFO("window " << patch.window.dims().nx << " x " << patch.window.dims().ny << " x " << patch.window.dims().nz
                   << ", grown " << patch.grows << " times");
    REQUIRE(patch.window.dims().count() < kDims.count() / 2);  // a window, not the grid
    const GradientMap edited = applyPatch(original, patch);
    sweepOut(layout, blade);
    test::requireSameMap(edited, rebuild(layout));
    // The voxels that became surface face the blade: their normals point at its axis (along the
    // rims, where the cut face meets the old surface, the smoothing blends the two), never away.
    int facing = 0, faces = 0, away = 0;
    for (const SurfaceVoxel& s : edited.surface) {
        if (isSurfaceSpecies(original.occ[s.voxel])) continue;
        ++faces;
        const Eigen::Vector3d c = kDims.coords(s.voxel).cast<double>() + Eigen::Vector3d::Constant(0.5);
        const Eigen::Vector3d toAxis = Eigen::Vector3d(34, 24, c.z()) - c;
        const double cosine = s.normal.cast<double>().dot(toAxis.normalized());
        facing += cosine > 0.3;
        away += cosine < -0.3;
    }
    INFO(facing << " of " << faces << " new surface voxels face the blade, " << away << " look away");
    REQUIRE(faces >= 20);
    REQUIRE(facing >= 0.8 * faces);
    REQUIRE(away == 0);
}

TEST_CASE("map edit: a blade that would take every bag is refused and changes nothing", "[mapedit]") {
    const GradientMap original = rebuild(layoutOf());
    BladeSweep blade;
    blade.a = Eigen::Vector3d(0, 24, 14);
    blade.b = Eigen::Vector3d(56, 24, 14);
    blade.radius = 60;  // the whole grid
    CHECK_THROWS_AS(cut(original, blade), std::domain_error);
    blade.radius = 2;  // a blade that meets no bag: an empty patch
    blade.a = blade.b = Eigen::Vector3d(1, 1, 1);
    CHECK(cut(original, blade).empty());
    CHECK(applyPatch(original, cut(original, blade)).occ == original.occ);
}
