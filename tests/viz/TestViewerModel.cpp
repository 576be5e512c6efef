// The viewer's GL-free model of its panel and pointer: rates and round trips measured from
// given times, plot histories, the mouse probe on the camera's view plane, and sliders that
// become exactly the commands for what changed.
#include "client/RoundTrip.hpp"
#include "scene/Controls.hpp"
#include "scene/MouseProbe.hpp"
#include "scene/Telemetry.hpp"

#include <catch2/catch.hpp>

using namespace bop;
using namespace bop::viz;

TEST_CASE("rates: events per second over the window, zero when they stop", "[viz]") {
    RateMeter m(2.0);
    CHECK(m.rateHz(0) == 0);
    for (int k = 0; k <= 30; ++k) m.tick(0.1 * k);  // 10 Hz for 3 s
    CHECK(m.rateHz(3.0) == Approx(10).epsilon(1e-9));
    m.tick(3.05);  // then 20 Hz
    for (int k = 1; k <= 40; ++k) m.tick(3.05 + 0.05 * k);
    CHECK(m.rateHz(5.05) == Approx(20).epsilon(1e-9));
    CHECK(m.rateHz(8.0) == 0);  // nothing in the last 2 s
}

TEST_CASE("probe round trip: the first feedback naming a probe, replaced probes never count", "[viz]") {
    protocol::RoundTrip rt;
    rt.sent(1, 10.000);
    rt.sent(2, 10.001);  // replaced before the server applied 1? then 1 never gets its feedback
    rt.feedback(2, 10.005);
    rt.feedback(2, 10.006);  // the same probe at the next step: not a new round trip
    CHECK(rt.count() == 1);
    CHECK(rt.lastMs() == Approx(4.0).margin(1e-9));
    for (int k = 3; k < 103; ++k) {
        rt.sent(std::uint64_t(k), k);
        rt.feedback(std::uint64_t(k), k + 0.001 * (k - 2));  // 1 .. 100 ms
    }
    CHECK(rt.count() == 101);
    CHECK(rt.percentileMs(50) == Approx(50).margin(1.01));
    CHECK(rt.percentileMs(99) == Approx(99).margin(1.01));
    CHECK(rt.percentileMs(100) == Approx(100).margin(1e-6));
    rt.feedback(7, 200);  // an old sequence number: nothing pending for it
    CHECK(rt.count() == 101);
}

TEST_CASE("plots keep the newest samples and start again when the server does", "[viz]") {
    PlotHistory h(4);
    for (int k = 0; k < 6; ++k) h.push({double(k), -double(k), 0.5 * k, 2.0 * k});
    REQUIRE(h.size() == 4);
    CHECK(h.series(&PlotSample::energy) == std::vector<float>{-2, -3, -4, -5});
    CHECK(h.series(&PlotSample::probeForce) == std::vector<float>{4, 6, 8, 10});
    h.push({1.0, 0, 0, 0});  // simulation time went back: a restarted server
    CHECK(h.size() == 1);
}

TEST_CASE("mouse probe: under the pointer at its depth, the wheel moves it along the view", "[viz]") {
    OrbitCamera cam;
    const double aspect = 4.0 / 3.0;
    cam.fit(Eigen::AlignedBox3d(Eigen::Vector3d(-5, -5, -5), Eigen::Vector3d(5, 5, 5)), aspect);
    MouseProbe p(0.5);
    CHECK_FALSE(p.active());
    p.press(0.2, -0.3, cam, aspect);
    CHECK(p.active());
    // The first press: on the plane through the target, under the pointer.
    CHECK((p.position() - cam.target()).dot(cam.forward()) == Approx(0).margin(1e-9));
    Eigen::Vector3d ndc = cam.project(p.position(), aspect);
    CHECK(ndc.x() == Approx(0.2));
    CHECK(ndc.y() == Approx(-0.3));
    p.wheel(4, cam);  // 2 length units deeper
    const double depth = (p.position() - cam.eye()).dot(cam.forward());
    CHECK(depth == Approx(cam.distance() + 2.0));
    p.drag(-0.5, 0.4, cam, aspect);  // follows the pointer, keeps its depth
    ndc = cam.project(p.position(), aspect);
    CHECK(ndc.x() == Approx(-0.5));
    CHECK(ndc.y() == Approx(0.4));
    CHECK((p.position() - cam.eye()).dot(cam.forward()) == Approx(depth));
    CHECK(p.changed());
    protocol::Probe m = p.message(123, 1.5, 2.0);
    CHECK(m.active);
    CHECK(m.position == p.position());
    CHECK(m.k0 == 1.5);
    CHECK(m.k1 == 2.0);
    CHECK_FALSE(p.changed());
    p.release();
    CHECK(p.changed());
    CHECK_FALSE(p.message(124, 1, 1).active);
    const Eigen::Vector3d kept = p.position();
    p.drag(0.9, 0.9, cam, aspect);  // not pressed: nothing moves
    CHECK(p.position() == kept);
}

namespace {

protocol::SceneInfo twoSpecies() {
    protocol::SceneInfo s;
    s.species = {{"skin", protocol::SpeciesKind::Surface, {200, 50, 50, 255}},
                 {"fill", protocol::SpeciesKind::Volume, {50, 50, 200, 255}}};
    s.tunables = {{1, 0.5, 0.5, 1}, {0.3, 0, 0, 0}, {0.3, 0, 0, 0}, {1.0, 2.0}, {0.3, 0.3}, 1, 1};
    return s;
}

}  // namespace

TEST_CASE("sliders start from the server's values and send exactly what changed", "[viz]") {
    Controls c(twoSpecies());
    CHECK(c.species() == 2);
    CHECK(c.commands().empty());  // nothing moved
    c.now.lj[1] = 0.8;            // row 1 (skin receives), column 2 (from fill)
    c.now.coPlanar[0] = 0.1;
    c.now.dragV[1] = 4.0;
    c.now.k0 = 1.5;
    const std::vector<protocol::Command> sent = c.commands();
    REQUIRE(sent.size() == 4);
    const auto param = [&](std::size_t i) { return std::get<protocol::SetParameter>(sent[i].body); };
    CHECK(param(0).name == "lj");
    CHECK(param(0).speciesA == 1);
    CHECK(param(0).speciesB == 2);
    CHECK(param(0).value == 0.8);
    CHECK(param(1).name == "co_planar");
    CHECK(param(1).speciesA == 1);
    CHECK(param(1).speciesB == 1);
    CHECK(param(2).name == "drag_v");
    CHECK(param(2).speciesA == 2);
    CHECK(param(2).value == 4.0);
    CHECK(param(3).name == "k0");
    CHECK(c.commands().empty());  // sent once
    c.now.lj[1] = 0.8;            // the same value again: nothing to send
    CHECK(c.commands().empty());

    protocol::SceneInfo none = twoSpecies();
    none.tunables = {};  // a server that sends no tunables: weights 1, nothing sent until moved
    Controls d(none);
    CHECK(d.now.lj == std::vector<double>(4, 1.0));
    CHECK(d.commands().empty());
}

TEST_CASE("the panel's one-off commands carry what was chosen", "[viz]") {
    const protocol::Command seed = seedCommand(2, {1, 2, 3});
    CHECK(std::get<protocol::SeedParticle>(seed.body).species == 2);
    CHECK(std::get<protocol::SeedParticle>(seed.body).position == Eigen::Vector3d(1, 2, 3));
    CHECK(std::get<protocol::SetBirth>(birthCommand(1, false).body).enabled == false);
    const auto step = std::get<protocol::RunControl>(runCommand(protocol::RunAction::SingleStep, 5).body);
    CHECK(step.action == protocol::RunAction::SingleStep);
    CHECK(step.steps == 5);
    const auto rec = std::get<protocol::Record>(recordCommand(true, "take1.mcap").body);
    CHECK(rec.start);
    CHECK(rec.path == "take1.mcap");
}
