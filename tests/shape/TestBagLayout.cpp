// Several bags in one map (shape/BagLayout.hpp, docs/shape-pipeline.md "Several bags"): each
// voxel labelled for the bag that holds it when bags lie side by side, touch, or nest in one of
// two, in any listed order; each bag's own closed surface where two touch; the map's forces
// never pull a particle into another object; the bags' parents kept by the map file.
#include "ShapeTestUtil.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "core/MapField.hpp"
#include "shape/BagLayout.hpp"

#include <catch2/catch.hpp>

#include <functional>

using namespace bop;
using Inside = std::function<bool(const Eigen::Vector3d&)>;

namespace {

const Dims kDims{60, 30, 30};

Mask maskOf(const Inside& in) {
    Mask m(kDims, 0);
    for (std::size_t v = 0; v < kDims.count(); ++v)
        m.data[v] = in(kDims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5));
    return m;
}

Inside ball(const Eigen::Vector3d& c, double r) {
    return [=](const Eigen::Vector3d& x) { return (x - c).norm() < r; };
}
Inside box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return [=](const Eigen::Vector3d& x) { return (x.array() > lo.array()).all() && (x.array() < hi.array()).all(); };
}

struct Built {
    shape::BagLayout layout;
    GradientMap map;
};

Built build(const std::vector<Inside>& bags) {
    shape::ShapeSpec spec;
    spec.sceneFile = "layout.toml";
    std::vector<Mask> masks;
    for (std::size_t b = 0; b < bags.size(); ++b) {
        spec.bags.push_back({"bag" + std::to_string(b + 1), "shape.bag[" + std::to_string(b) + "]", nullptr, {}});
        masks.push_back(maskOf(bags[b]));
    }
    Built out{shape::arrangeBags(spec, masks, 0), {}};
    VoxelGrid g;
    g.dims = kDims;
    SurfaceGeometryParams p;
    p.sigmaVoxels = 1.5;
    out.map = shape::buildGradientMap(g, out.layout, 2.0, p);
    return out;
}

int occAt(const GradientMap& m, int i, int j, int k) {
    return m.occ[kDims.index(i, j, k)];
}

std::string errorOf(const std::vector<Inside>& bags) {
    try {
        build(bags);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("each voxel labelled for its bag: side by side, touching, nested in one of two", "[shape][bags]") {
    SECTION("side by side") {
        const Built b = build({ball({15, 15, 15}, 10), ball({45, 15, 15}, 10)});
        CHECK(b.layout.parent == std::vector<std::uint8_t>{0, 0, 0});
        CHECK(occAt(b.map, 15, 15, 15) == 2);
        CHECK(occAt(b.map, 45, 15, 15) == 4);
        CHECK(occAt(b.map, 30, 15, 15) == 0);
        CHECK(occAt(b.map, 5, 15, 15) == 1);   // the left ball's edge
        CHECK(occAt(b.map, 35, 15, 15) == 3);  // the right ball's edge
    }
    SECTION("touching: each bag its own closed surface along the shared face") {
        const Inside a = box({5, 5, 5}, {25, 25, 25}), c = box({25, 5, 5}, {45, 25, 25});
        const Built both = build({a, c});
        const Built alone = build({a});
        CHECK(both.layout.parent == std::vector<std::uint8_t>{0, 0, 0});
        CHECK(occAt(both.map, 24, 15, 15) == 1);  // the left box's last layer
        CHECK(occAt(both.map, 25, 15, 15) == 3);  // the right box's first layer
        CHECK(occAt(both.map, 23, 15, 15) == 2);
        CHECK(occAt(both.map, 26, 15, 15) == 4);
        std::size_t differ = 0;
        for (std::size_t v = 0; v < kDims.count(); ++v)
            differ +=
                (both.map.occ[v] == 1 || both.map.occ[v] == 2) != (alone.map.occ[v] == 1 || alone.map.occ[v] == 2) ||
                (both.map.occ[v] == 1) != (alone.map.occ[v] == 1);
        CHECK(differ == 0);  // the left box labelled as if the right one were not there
        // Normals of each side of the shared face point out of their own bag.
        const auto normalAt = [&](int i) {
            return both.map.nearestSurface(kDims.index(i, 15, 15)).normal.cast<double>();
        };
        CHECK(normalAt(24).x() > 0.99);
        CHECK(normalAt(25).x() < -0.99);
    }
    SECTION("nested in one of two, the inner bag listed first") {
        const Built b = build({ball({15, 15, 15}, 5), ball({15, 15, 15}, 12), ball({45, 15, 15}, 10)});
        CHECK(b.layout.parent == std::vector<std::uint8_t>{0, 2, 0, 0});
        CHECK(occAt(b.map, 15, 15, 15) == 2);  // the inner ball's volume
        CHECK(occAt(b.map, 19, 15, 15) == 1);  // its surface
        CHECK(occAt(b.map, 22, 15, 15) == 4);  // the ball around it
        CHECK(occAt(b.map, 26, 15, 15) == 3);
        CHECK(occAt(b.map, 45, 15, 15) == 6);  // the ball beside
        CHECK(b.map.bagWithin(1, 2));
        CHECK(!b.map.bagWithin(1, 3));
        CHECK(!b.map.bagWithin(2, 1));
        // The map file keeps the parents.
        test::TempDir dir("bag-layout");
        writeGradientMaps(dir.file("m.bopgm"), {b.map}, 7);
        const auto back = readGradientMaps(dir.file("m.bopgm"), 7);
        REQUIRE(back);
        CHECK(back->front().bagParent == b.map.bagParent);
        for (std::size_t v = 0; v < kDims.count(); v += 7)
            CHECK(back->front().signedDistance(v) == b.map.signedDistance(v));
    }
}

TEST_CASE("bags that overlap with neither inside the other, or are the same, are refused", "[shape][bags]") {
    CHECK_THAT(errorOf({ball({20, 15, 15}, 10), ball({30, 15, 15}, 10)}),
               Catch::Contains("layout.toml") && Catch::Contains("shape.bag[1]") &&
                   Catch::Contains("'bag2' and bag 'bag1' overlap") && Catch::Contains("lie outside bag 'bag1'"));
    CHECK_THAT(errorOf({ball({20, 15, 15}, 10), ball({20, 15, 15}, 10)}),
               Catch::Contains("shape.bag[1]") && Catch::Contains("same voxels as bag 'bag1'"));
}

TEST_CASE("the map never pulls a particle into another object", "[shape][bags]") {
    // Touching boxes: left = bag 1 (species 1, 2), right = bag 2 (species 3, 4).
    const Built b = build({box({5, 5, 5}, {25, 25, 25}), box({25, 5, 5}, {45, 25, 25})});
    const GradientMap& m = b.map;
    const core::MapField field(m, core::Interpolation::Nearest);
    std::size_t inOther = 0, outsideNearOther = 0;
    for (int species = 1; species <= 4; ++species) {
        const int own = bagOfSpecies(species), other = 3 - own;
        const auto kind = isSurfaceSpecies(species) ? core::ParticleKind::Surface : core::ParticleKind::Volume;
        for (std::size_t v = 0; v < kDims.count(); ++v) {
            const Eigen::Vector3d p = kDims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
            const Eigen::Vector3d f = field.ruleAtVoxel(v, kind, species, p);
            const Eigen::Vector3d d = m.delta(v).cast<double>();
            if (m.inBag(v, other)) {  // in the other box: towards its surface, or out through it
                ++inOther;
                const Eigen::Vector3d out =
                    m.occ[v] == surfaceSpeciesOfBag(other) ? m.nearestSurface(v).normal.cast<double>() : d;
                INFO("species " << species << " at " << p.transpose() << ": force " << f.transpose());
                CHECK(f.dot(out) > 0);
            } else if (m.occ[v] == 0 && bagOfSpecies(m.nearestSpecies(v)) == other) {
                ++outsideNearOther;  // nearer the other box than its own: never towards it
                CHECK(f.dot(d) <= 0);
            }
        }
    }
    CHECK(inOther > 10000);
    CHECK(outsideNearOther > 10000);
}
