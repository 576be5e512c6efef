// Materials in a scene (app/scene/Material.hpp, docs/physics.md §8): each bag's Young's modulus,
// Poisson ratio, density and relaxation time become the scene's units and the bonds, weights, map
// stiffnesses and drags of its species; bad tables stop with the key.
#include "TestUtil.hpp"
#include "app/scene/SceneConfig.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <utility>

using namespace bop;

namespace {

// A liver-like block with a stiffer ball inside it, one tissue each.
const std::string kTwoTissues = R"(
[grid]
voxel_size_mm = 1.0
r0_voxels = 2.0
[[shape.bag]]
name = "liver"
source = "superellipsoid"
radii_mm = [12, 12, 8]
exponents = [0.2, 0.2]
[[shape.bag]]
name = "tumour"
source = "sphere"
radius_mm = 4
[[material]]
bags = ["liver"]
young_kpa = 5
density_kg_m3 = 1060
relaxation_s = 0.05
[[material]]
bags = ["tumour"]
young_kpa = 25
relaxation_s = 0.2
[probe]
radius_mm = 6
)";

app::Scene load(const test::TempDir& dir, const std::string& text) {
    return app::loadScene(test::writeText(dir.file("scene.toml"), text));
}

void requireRefused(const std::string& text, const std::string& key, const std::string& what) {
    const test::TempDir dir("material-scene");
    try {
        load(dir, text);
        FAIL("the scene was accepted");
    } catch (const Error& e) {
        CHECK_THAT(e.what(), Catch::Contains(key) && Catch::Contains(what));
    }
}

}  // namespace

TEST_CASE("two tissues: units from the stiffer, each bag's weights from its own modulus", "[physics][material]") {
    const test::TempDir dir("material-scene");
    const app::Scene s = load(dir, kTwoTissues);
    const core::Model& m = *s.model;
    const UnitSystem& u = m.units;
    REQUIRE(u.physical);
    REQUIRE(s.calibration);
    // Lengths: 1 mm voxels, r0 = 2 voxels = sqrt 3 simulation units.
    CHECK(u.lengthMm == Approx(2 / std::sqrt(3.0)));
    // The stiffer tissue has weight 1: its P-wave modulus lambda + 2 mu is the unit's kPWaveModulus.
    CHECK(s.calibration->weight[0] == Approx(0.2));
    CHECK(s.calibration->weight[1] == Approx(1.0));
    const double nu = 0.3;
    CHECK(u.toKpa(app::kPWaveModulus) == Approx(25.0 * (1 - nu) / ((1 + nu) * (1 - 2 * nu))));
    // Each tissue's bonds: mu = k / (sqrt 2 r0) = E / (2 (1 + nu)); lambda = mu + B.
    for (const auto& [species, e] : {std::pair{2, 5.0}, std::pair{3, 25.0}}) {
        const double mu = m.species[std::size_t(species)].bondStiffness / (std::sqrt(2.0) * kR0);
        CHECK(u.toKpa(mu) == Approx(e / (2 * (1 + nu))));
        CHECK(u.toKpa(mu + m.species[std::size_t(species)].bondBulk) == Approx(e * nu / ((1 + nu) * (1 - 2 * nu))));
    }
    // A particle carries its fcc cell of the first tissue's density: r0^3 / sqrt 2 at r0 = 2 mm.
    CHECK(u.massKg == Approx(1060 * std::pow(2e-3, 3) / std::sqrt(2.0)));
    // LJ weights: none within a tissue (its bonds hold it), two springs in series across the border.
    CHECK(s.params.lj(1, 1) == 0.0);
    CHECK(s.params.lj(3, 4) == 0.0);
    CHECK(s.params.lj(2, 4) == Approx(2 * 0.2 / 1.2));
    CHECK(s.params.lj(4, 2) == Approx(s.params.lj(2, 4)));
    // The sheet's own terms scale with the tissue, the map's spring with its bond (shape_hold).
    CHECK(s.params.coNormal(1, 1) == Approx(app::kSheetWeight * 0.2));
    CHECK(s.params.coPlanar(3, 3) == Approx(app::kSheetWeight));
    CHECK(m.species[2].alphaForceGm == Approx(app::Material::kDefaultShapeHold * m.species[2].bondStiffness));
    CHECK(m.species[4].alphaForceGm == Approx(app::Material::kDefaultShapeHold * m.species[4].bondStiffness));
    // The sphere's contact: 10 times the stiffest bond.
    REQUIRE(m.probeSphere);
    CHECK(m.probeSphere->stiffness == Approx(10 * m.species[4].bondStiffness));
    // Drags: a particle's speed falls by e in the stated relaxation time (mass 1: beta = 1 / t).
    CHECK(u.toS(1 / s.params.drag[1].v) == Approx(0.05));
    CHECK(u.toS(1 / s.params.drag[4].v) == Approx(0.2));
    CHECK(s.params.drag[1].w == Approx(m.integration.inertia * s.params.drag[1].v));
    // The probe is a sphere of 6 mm.
    REQUIRE(m.probeSphere);
    CHECK(u.toMm(m.probeSphere->radius) == Approx(6.0));
}

TEST_CASE("mass scaling slows the clock and leaves the forces as they are", "[physics][material]") {
    const test::TempDir dir("material-scene");
    const app::Scene plain = load(dir, kTwoTissues);
    const app::Scene scaled = load(dir, kTwoTissues + "[units]\nmass_scaling = 100\n");
    CHECK(scaled.model->units.timeS / plain.model->units.timeS == Approx(10.0));
    CHECK(scaled.model->units.forceN() == Approx(plain.model->units.forceN()));
    CHECK(scaled.params.lj(2, 4) == plain.params.lj(2, 4));
    CHECK(scaled.model->species[2].bondStiffness == plain.model->species[2].bondStiffness);
}

TEST_CASE("a scene without materials keeps its hand-set weights and knows its lengths only", "[physics][material]") {
    const test::TempDir dir("material-scene");
    const app::Scene s = load(dir,
                              "[grid]\nvoxel_size_mm = 1.5\nr0_voxels = 1.4\n[[shape.bag]]\nsource = \"sphere\"\n"
                              "radius_mm = 6\n");
    CHECK_FALSE(s.model->units.physical);
    CHECK(s.model->units.lengthMm == Approx(1.5 * 1.4 / std::sqrt(3.0)));
    CHECK(s.params.lj(1, 2) == 1.0);
    CHECK(s.params.drag[1].v == 1.0);
    CHECK_FALSE(s.model->probeSphere);
}

TEST_CASE("bad material tables name their key", "[physics][material]") {
    const std::string bag =
        "[grid]\nvoxel_size_mm = 1.0\n[[shape.bag]]\nname = \"a\"\nsource = \"sphere\"\n"
        "radius_mm = 5\n";
    requireRefused(bag + "[[material]]\nbags = [\"b\"]\nyoung_kpa = 5\n", "material[0].bags", "no bag is named 'b'");
    requireRefused(bag + "[[material]]\nyoung_kpa = -5\n", "material[0].young_kpa", "above 0 kPa");
    requireRefused(bag + "[[material]]\nyoung_kpa = 5\npoisson = 0.5\n", "material[0].poisson", "below 0.5");
    requireRefused(bag + "[[material]]\nyoung_kpa = 5\npoisson = 0.2\n", "material[0].poisson", "from 0.25");
    requireRefused(bag + "[[material]]\nyoung_kpa = 5\n[construction]\nmethod = \"birth\"\n", "construction",
                   "is placed");
    requireRefused(bag + "[[material]]\nyoung_kpa = 5\n[interactions]\nlj = [[1, 1], [1, 1]]\n", "interactions",
                   "give either");
    requireRefused(bag + "[units]\nmass_scaling = 10\n", "units.mass_scaling", "[[material]]");
    requireRefused(bag + "[[material]]\nyoung_kpa = 5\n[units]\nmass_scaling = 0.5\n", "units.mass_scaling",
                   "1 or more");
    requireRefused(bag +
                       "[[shape.bag]]\nname = \"c\"\nsource = \"sphere\"\nradius_mm = 2\ncenter_mm = [20, 0, 0]\n"
                       "[[material]]\nbags = [\"a\"]\nyoung_kpa = 5\n",
                   "material", "bag 'c' has no material");
    requireRefused(bag + "[probe]\ncontact_stiffness = 3\n", "probe.contact_stiffness", "radius_mm");
}
