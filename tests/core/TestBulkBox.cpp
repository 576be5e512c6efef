// The bulk-material box of a scene: whole fcc cells at nearest distance r0, none lost to
// rounding when the box is exactly n cells across (the benchmark's 10,976-particle box).
#include "TestUtil.hpp"
#include "app/SceneConfig.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

using namespace bop;

TEST_CASE("a box of n whole fcc cells holds 4 n^3 particles at nearest distance r0", "[core][bulk]") {
    test::TempDir dir("bulk");
    for (int cells : {3, 14, 29}) {
        char side[64];
        std::snprintf(side, sizeof side, "%.17g", cells * std::sqrt(2.0));
        const std::string path = test::writeText(dir.file("bulk.toml"), std::string("[box]\nsize_r0 = [") + side + ", " +
                                                     side + ", " + side + "]\nspacing_r0 = 1.0\nperiodic = true\n"
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
