// The FIRE minimiser (core/Fire.hpp): its step and mixing schedule, a checkpoint's state going on
// as the minimiser would, and a disordered LJ box brought nearer its minimum than the damped
// dynamics gets it in as many steps.
#include "TestUtil.hpp"
#include "app/scene/SceneConfig.hpp"
#include "core/Fire.hpp"
#include "core/Simulation.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

using namespace bop;

TEST_CASE("FIRE stops at negative power, grows its step after the delay and turns v towards F", "[core][fire]") {
    core::FireParams p;  // delay 5, grow 1.1, shrink 0.5, alpha 0.1, decay 0.99, dt max 6
    core::Fire fire(p, 0.03);
    // From rest the power is zero: stops, without a cut while the first steps last.
    for (int k = 0; k < int(p.delaySteps); ++k) {
        const core::FireKick kick = fire.next({0, 0, 1, 0, 0});
        CHECK(kick.stop);
        CHECK(kick.dt == 0.03);
        CHECK(kick.back == Approx(0.015));
    }
    // Positive power: mixing with alpha and |v| / |F|; the step grows only after the delay.
    double dt = 0.03, alpha = p.alphaStart;
    for (int k = 1; k <= 40; ++k) {
        const core::FireKick kick = fire.next({2.0, 4.0, 16.0, 1.0, 4.0});  // |v| 2, |F| 4, |w| 1, |tau| 2
        if (k > p.delaySteps) dt = std::min(dt * p.grow, p.dtMaxFactor * 0.03), alpha *= p.alphaShrink;
        INFO("step " << k);
        CHECK_FALSE(kick.stop);
        CHECK(kick.dt == Approx(dt).epsilon(1e-14));
        CHECK(kick.keep == Approx(1 - alpha).epsilon(1e-14));
        CHECK(kick.alongForce == Approx(alpha * 0.5).epsilon(1e-14));
        CHECK(kick.alongTorque == Approx(alpha * 0.5).epsilon(1e-14));
    }
    CHECK(dt == Approx(6 * 0.03));  // capped
    // Negative power: stop, half a step back, the step halved and alpha back to its start.
    const core::FireKick stop = fire.next({-1.0, 4.0, 16.0, 0, 0});
    CHECK(stop.stop);
    CHECK(stop.dt == Approx(3 * 0.03));
    CHECK(stop.back == Approx(0.5 * 3 * 0.03));
    const core::FireKick after = fire.next({1.0, 4.0, 16.0, 0, 0});
    CHECK(after.keep == Approx(1 - p.alphaStart));
    CHECK(after.alongTorque == 0.0);  // no torque: no turn towards it
}

TEST_CASE("FIRE from a checkpoint's state goes on as the minimiser it was taken from", "[core][fire]") {
    std::vector<core::FirePower> sums;
    for (int k = 0; k < 60; ++k) sums.push_back({std::sin(0.37 * k) + 0.3, 1.0 + k, 2.0 + k, 0.5, 1.5});
    core::Fire whole({}, 0.02);
    std::optional<core::Fire> resumed;
    for (int k = 0; k < 60; ++k) {
        const core::FireKick a = whole.next(sums[std::size_t(k)]);
        if (k == 25) resumed.emplace(core::FireParams{}, 0.02, whole.state());
        if (k <= 25) continue;
        const core::FireKick b = resumed->next(sums[std::size_t(k)]);
        INFO("step " << k);
        CHECK(a.dt == b.dt);
        CHECK(a.stop == b.stop);
        CHECK(a.keep == b.keep);
        CHECK(a.alongForce == b.alongForce);
    }
}

namespace {

// A periodic fcc box of 4 x 3^3 LJ particles, each moved up to 0.15 r0 off its site.
std::shared_ptr<const core::Model> jitteredBox(core::Particles& p) {
    test::TempDir dir("fire-box");
    const std::string path =
        test::writeText(dir.file("box.toml"),
                        "[box]\nsize_r0 = [4.242640687119285, 4.242640687119285, 4.242640687119285]\n"
                        "spacing_r0 = 1.0\njitter_r0 = 0.15\nperiodic = true\n"
                        "[[species]]\nname = \"bulk\"\nkind = \"volume\"\n[dynamics]\ntime_step = 0.02\n");
    const app::Scene scene = app::loadScene(path);
    p = app::bulkLattice(scene);
    return scene.model;
}

// The pair energy per particle after `steps` steps of the minimiser or the damped dynamics.
double pairEnergyAfter(bool minimise, int steps) {
    core::Particles p;
    const auto model = jitteredBox(p);
    core::Simulation sim(model, p);
    if (minimise) sim.minimise(core::FireParams{});
    sim.run(steps);
    sim.refreshForces();
    return sim.stats().forces.pairEnergy / double(p.size());
}

}  // namespace

TEST_CASE("FIRE brings a disordered LJ box nearer its minimum than the damped dynamics in as many steps",
          "[core][fire]") {
    const double start = pairEnergyAfter(false, 0);
    const double dynamics = pairEnergyAfter(false, 100), fire = pairEnergyAfter(true, 100);
    const double minimum = pairEnergyAfter(false, 3000);  // the damped dynamics, long after: the minimum
    INFO("energy per particle: start " << start << ", after 100 steps of the dynamics " << dynamics << " and of FIRE "
                                       << fire << ", after 3000 of the dynamics " << minimum);
    CHECK(dynamics < start);
    CHECK(fire < dynamics);
    CHECK(std::abs(fire - minimum) < 0.5 * (dynamics - minimum));  // at least twice as close (3.4 times, 2026-12-06)
}
