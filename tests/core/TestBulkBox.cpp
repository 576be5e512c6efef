// The bulk-material box of a scene: whole fcc cells at nearest distance r0, none lost to
// rounding when the box is exactly n cells across (the benchmark's 10,976-particle box).
#include "TestUtil.hpp"
#include "app/scene/SceneConfig.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

using namespace bop;

TEST_CASE("a box of n whole fcc cells holds 4 n^3 particles at nearest distance r0", "[core][bulk]") {
    test::TempDir dir("bulk");
    for (int cells : {3, 14, 29}) {
        char side[64];
        std::snprintf(side, sizeof side, "%.17g", cells * std::sqrt(2.0));
        const std::string path = test::writeText(dir.file("bulk.toml"),
                                                 std::string("[box]\nsize_r0 = [") + side + ", " + side + ", " + side +
                                                     "]\nspacing_r0 = 1.0\nperiodic = true\n"
                                                     "[[species]]\nname = \"bulk\"\nkind = \"volume\"\n");
        const app::Scene scene = app::loadScene(path);
        const core::Particles p = app::bulkLattice(scene);
        INFO(cells << " cells per edge");
        REQUIRE(p.size() == std::size_t(4 * cells * cells * cells));
        const Eigen::Vector3d L = scene.model->box.size();
        double nearest = HUGE_VAL;
        for (std::size_t j = 1; j < p.size(); ++j) {
            Eigen::Vector3d r = p.pos[j] - p.pos[0];
            for (int a = 0; a < 3; ++a) r[a] -= L[a] * std::round(r[a] / L[a]);
            nearest = std::min(nearest, r.norm());
        }
        CHECK(nearest == Approx(core::kR0).epsilon(1e-12));
    }
}

TEST_CASE("a scene's probe keeps the ranges a client's probe must keep", "[core][scene][probe]") {
    test::TempDir dir("probe-range");
    const auto load = [&](const std::string& probe) {
        const std::string path = test::writeText(dir.file("probe.toml"),
                                                 "[box]\nsize_r0 = [6.0, 6.0, 6.0]\n"
                                                 "[[species]]\nname = \"bulk\"\nkind = \"volume\"\n[probe]\n" +
                                                     probe);
        try {
            const app::Scene s = app::loadScene(path);
            return std::string("k1 ") + std::to_string(s.probe.params.k1);
        } catch (const std::exception& e) {
            return std::string(e.what()).find(path) != std::string::npos ? std::string(e.what()) : "no path";
        }
    };
    CHECK(load("k0 = 10.0\nk1 = 50.0\n") == "k1 50.000000");
    CHECK_THAT(load("k1 = 50.5\n"), Catch::Contains("probe.k1") && Catch::Contains("0.000000..50.000000"));
    CHECK_THAT(load("k1 = -1.0\n"), Catch::Contains("probe.k1"));
    CHECK_THAT(load("k0 = 0.05\n"), Catch::Contains("probe.k0"));
    CHECK_THAT(load("k0 = nan\n"), Catch::Contains("probe.k0"));
}
