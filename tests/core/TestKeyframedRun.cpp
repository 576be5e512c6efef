// A keyframed bag in one process: the map in force switches at the stated times and the shape
// force is the blend of two frames' forces; the blood's pressure against the mechanical
// pressure on the walls of an ideal gas; the averaged pressure cycle of app/CardiacSeries.
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/cardiac/CardiacSeries.hpp"
#include "app/scene/RunStart.hpp"
#include "shape/KeyframeTestScene.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

using namespace bop;

TEST_CASE("keyframes at one process: the map switches every frame duration and the force is the blend", "[keyframes]") {
    test::TempDir dir("keyframes");
    app::Scene scene = app::loadScene(test::writeKeyframeScene(dir.path.string(), 0.1, true));
    test::OneProcessRun sim(scene);
    const auto frames = sim->mapInForce().frames;  // this process's windows of every keyframe: the whole maps
    REQUIRE(frames.size() == 2);
    REQUIRE(sim->frameVolumes().size() == 2);
    CHECK(sim->frameVolumes()[1].bagVoxels > 3 * sim->frameVolumes()[0].bagVoxels);  // radius 6 to 9 voxels
    // One volume particle between the two balls' surfaces: outside the small one, inside the large.
    const double h = core::kR0 / 2;
    sim->particles().add(Eigen::Vector3d(12 + 7.5, 12.3, 11.8) * h, 2, 1);
    sim->refreshForces();
    const core::MapField small(*frames[0], scene.model->interpolation), large(*frames[1], scene.model->interpolation);
    const double alpha = sim->model().species[2].alphaForceGm;
    int switches = 0, last = 0;
    for (int s = 0; s < 40; ++s) {
        sim->step();
        const long long step = sim->stats().step;  // forces of time step * dt = step * 0.02: frame every 5 steps
        const core::KeyframeAt at = sim->stats().keyframe;
        INFO("step " << step);
        CHECK(at.a == int((step / 5) % 2));
        CHECK(at.b == 1 - at.a);
        CHECK(at.w == Approx(double(step % 5) / 5).margin(1e-9));
        CHECK(sim->mapInForce().map() == frames[std::size_t(at.a)]);
        switches += at.a != last;
        last = at.a;
        const Eigen::Vector3d x = sim->particles().pos[0], n = sim->particles().normal[0];
        const core::MapField& fa = at.a == 0 ? small : large;
        const core::MapField& fb = at.b == 0 ? small : large;
        const Eigen::Vector3d expected = alpha * ((1 - at.w) * fa.sample(core::ParticleKind::Volume, 2, x, n).force +
                                                  at.w * fb.sample(core::ParticleKind::Volume, 2, x, n).force);
        CHECK((sim->particles().force[0] - expected).norm() < 1e-12);
        // The blood volume is the blend of the two frames' volume voxels.
        const double v0 = sim->frameVolumes()[0].volumeVoxels, v1 = sim->frameVolumes()[1].volumeVoxels;
        const double va = at.a == 0 ? v0 : v1, vb = at.b == 0 ? v0 : v1;
        CHECK(sim->stats().bloodVolume == Approx(((1 - at.w) * va + at.w * vb) * h * h * h));
    }
    CHECK(switches == 8);
    CHECK(sim->particles().force[0].norm() > 0);  // the test saw a shape force at all
}

TEST_CASE("with LJ off the blood's pressure is N T / V and equals the walls' mechanical pressure within 2%",
          "[keyframes]") {
    test::TempDir dir("ideal-gas");
    // A ball of radius 14 voxels; the wall is the map's step from volume to surface voxels
    // (nearest rule), stiff; no pair forces and no drag on the gas. The step force heats the gas
    // as particles cross voxel faces within a step (T rises about tenfold here); the virial
    // theorem holds at every temperature, and both sides are averaged over the same steps.
    const std::string path = test::writeText(dir.file("gas.toml"), R"(
[grid]
voxel_size_mm = 1.0
r0_voxels = 2.0
padding_voxels = 3
[shape]
interpolation = "nearest"
[[shape.bag]]
source = "sphere"
radius_mm = 14.0
[[species]]
name = "wall"
[[species]]
name = "gas"
alpha_f_gm = 20.0
drag_v = 0.0
[interactions]
lj = [[0.0, 0.0], [0.0, 0.0]]
co_normal = [[0.0, 0.0], [0.0, 0.0]]
co_planar = [[0.0, 0.0], [0.0, 0.0]]
[construction]
method = "birth"  # no timeline: the gas below is all there is
)");
    app::Scene scene = app::loadScene(path);
    test::OneProcessRun sim(scene);
    const GradientMap& map = *sim->mapInForce().map();
    const double h = core::kR0 / map.r0Voxels, temperature = 0.4;
    std::mt19937_64 rng(7);
    std::normal_distribution<double> maxwell(0.0, std::sqrt(temperature));
    std::vector<std::size_t> volumeVoxels;
    for (std::size_t v = 0; v < map.occ.size(); ++v)
        if (map.occ[v] == 2) volumeVoxels.push_back(v);
    std::shuffle(volumeVoxels.begin(), volumeVoxels.end(), rng);  // one particle per voxel, none on top of another
    for (std::uint64_t id = 1; id <= 250; ++id) {
        const Eigen::Vector3i c = map.dims().coords(volumeVoxels[id]);
        const std::size_t k = sim->particles().add((c.cast<double>().array() + 0.5).matrix() * h, 2, id);
        sim->particles().vel[k] = Eigen::Vector3d(maxwell(rng), maxwell(rng), maxwell(rng));
    }
    sim->refreshForces();
    sim->run(300);  // the gas spreads into the ball
    double kinetic = 0, wall = 0, product = 0;
    const int steps = 2500;
    for (int s = 0; s < steps; ++s) {
        sim->step();
        const core::StepStats& st = sim->stats();
        kinetic += st.blood.mv2 / (3 * st.bloodVolume);
        wall += -st.forces.wallVirial / (3 * st.bloodVolume);
        product += core::virialPressure(st.blood.mv2, st.forces.virialVolume, st.bloodVolume);
    }
    const double n = sim->stats().blood.count, volume = sim->stats().bloodVolume;
    const double nTOverV = kinetic / steps;  // N T / V with T = sum m v^2 / (3 N)
    INFO("T " << nTOverV * volume / n << " (started at " << temperature << "), N " << n << ", V " << volume
              << ", N T / V " << nTOverV << ", wall pressure " << wall / steps << ", the product's pressure "
              << product / steps);
    CHECK(n == 250);
    CHECK(wall / steps == Approx(nTOverV).epsilon(0.02));
    CHECK(product / steps == Approx(wall / steps).epsilon(0.02));  // what the run reports is the walls' pressure
}

TEST_CASE("the averaged cycle finds a known pressure peak and scales it to 120 mmHg", "[keyframes]") {
    core::KeyframeSchedule k;
    k.frames = 8;
    k.frameDuration = 1.0;
    k.startTime = 2.0;
    k.firstFrame = 2;  // the cycle starts at phase 2/8
    app::PressureSettings settings;
    settings.skipCycles = 1;
    const std::vector<double> frameMl{120, 111, 73, 50, 57, 97, 102, 106};
    app::CardiacSeries series(settings, k, 2.0, frameMl);
    const double dt = 0.01;
    for (long long step = 1; step <= static_cast<long long>(4 * 8 / dt) + 200; ++step) {
        const double t = step * dt;
        const double phase = t < 2 ? 0.25 : (t - 2) / 8 + 0.25;
        const double pressure = 1.5 + std::cos(2 * M_PI * (phase - 0.4));  // peak at phase 0.4
        app::CardiacStep s;
        s.step = step, s.time = t, s.keyframe = k.at(t), s.count = 100, s.bloodVolume = 1.0, s.cavityVolume = 1.0;
        s.mv2 = 3 * pressure;  // P = (mv2 + 0) / (3 V)
        series.add(s);
        if (step % 50 == 0) series.addParticleVolume(60 + 30 * std::cos(2 * M_PI * phase));  // 90 to 30 mL
    }
    const app::CardiacCycle c = series.cycle();
    CHECK(c.cycles >= 2);
    CHECK(c.peakPhase == Approx(0.4).margin(0.01));
    CHECK(*std::max_element(c.fitMmHg.begin(), c.fitMmHg.end()) == Approx(120.0));
    CHECK(c.scale == Approx(120.0 / 2.5).epsilon(0.01));
    CHECK(c.efVoxels == Approx(70.0 / 120));
    CHECK(c.efParticles == Approx(60.0 / 90).margin(0.02));
    CHECK(series.rows().front().pressure == Approx(1.5 + std::cos(2 * M_PI * (0.25 - 0.4))).epsilon(1e-9));
}

TEST_CASE("bad keyframes and pressure tables stop with the file and key", "[keyframes]") {
    test::TempDir dir("keyframes-errors");
    const std::string good = test::writeKeyframeScene(dir.path.string(), 0.5, true);
    const std::string base = [&] {
        std::ifstream f(good);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    const auto fails = [&](const std::string& text, const std::string& name) {
        const std::string path = test::writeText(dir.file(name + ".toml"), text);
        try {
            app::loadScene(path);
        } catch (const std::exception& e) {
            return std::string(e.what()).find(path) != std::string::npos ? std::string(e.what())
                                                                         : std::string("no path");
        }
        return std::string("no error");
    };
    CHECK_THAT(fails(base + "period = 2.0\n", "both"),
               Catch::Contains("keyframes.frame_duration") && Catch::Contains("not both"));
    CHECK_THAT(fails(base + "first_frame = 2\n", "first"),
               Catch::Contains("keyframes.first_frame") && Catch::Contains("[0, 1]"));
    CHECK_THAT(fails(base + "first_frame = 4294967296\n", "first-wide"), Catch::Contains("keyframes.first_frame"));
    CHECK_THAT(fails(base + "start_time = nan\n", "nan"),
               Catch::Contains("keyframes.start_time") && Catch::Contains("finite"));
    std::string noDuration = base;
    noDuration.replace(noDuration.find("frame_duration = 0.5"), 20, "");
    CHECK_THAT(fails(noDuration, "neither"), Catch::Contains("keyframes.frame_duration") && Catch::Contains("either"));
    CHECK_THAT(fails(noDuration + "period = inf\n", "inf"),
               Catch::Contains("keyframes.period") && Catch::Contains("finite"));
    CHECK_THAT(fails(noDuration + "period = -2.0\n", "negative"),
               Catch::Contains("keyframes.period") && Catch::Contains("time step"));
    CHECK_THAT(fails(noDuration + "frame_duration = 0.001\n", "short"),
               Catch::Contains("keyframes.frame_duration") && Catch::Contains("time step"));
    CHECK_THAT(fails("[box]\n[keyframes]\nframe_duration = 1.0\n", "no-shape"),
               Catch::Contains("keyframes") && Catch::Contains("has none"));
    CHECK_THAT(fails(base + "[pressure]\naverage_steps = 0\n", "avg"), Catch::Contains("pressure.average_steps"));
    CHECK_THAT(fails(base + "[pressure]\nformula = 'ideal'\n", "formula"), Catch::Contains("pressure.formula"));
    const std::string sphere =
        "[grid]\nvoxel_size_mm = 1.0\n[shape]\n[[shape.bag]]\nsource = 'sphere'\nradius_mm = 5.0\n"
        "[keyframes]\nframe_duration = 1.0\n";
    CHECK_THAT(fails(sphere, "static"), Catch::Contains("one frame"));
    CHECK_THAT(fails("[box]\n[pressure]\n", "bulk"), Catch::Contains("pressure") && Catch::Contains("no [shape]"));
}
