// Keyframed maps across ranks: a bag built while its map cycles (a ball growing and shrinking
// every few steps) has, at whatever rank count mpiexec gave, the map frame of the schedule at
// every step, the single process's blood volume and pressure sums, and its particles.
#include "OneProcessRun.hpp"
#include "RankRun.hpp"
#include "TestUtil.hpp"
#include "app/scene/RunStart.hpp"
#include "parallel/MpiExchange.hpp"
#include "parallel/Session.hpp"
#include "shape/KeyframeTestScene.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <map>

using namespace bop;
using parallel::CartComm;
using testing::RankRun;

TEST_CASE("keyframes switch at the stated times at any rank count, as in one process", "[mpi][keyframes]") {
    test::TempDir dir("mpi-keyframes");  // frames of 0.5 time units (25 steps); the bag grows while its map cycles
    const std::string scene = test::writeKeyframeScene(dir.path.string(), 0.5, true, test::kGrowFromSeeds);
    app::Scene s = app::loadScene(scene);
    test::OneProcessRun serial(s);
    const CartComm comm(MPI_COMM_WORLD, serial.model()->box);
    core::SimulationOptions o;
    o.construction = core::Construction(s.construction, serial.timeline(), s.model->speciesCount());
    o.map = serial.mapSource();  // the windows of the serial run's cache
    o.params = s.params;
    RankRun run(serial.model(), core::Particles{}, o);
    const double dt = s.model->integration.dt;
    int switches = 0;
    for (long long step = 1; step <= 125; ++step) {
        serial->step();
        run.step();
        const core::Totals t = run.totals();
        const core::KeyframeAt want = s.model->keyframes.at(double(step) * dt);
        INFO("step " << step);
        REQUIRE(t.keyframe.a == want.a);
        CHECK(t.keyframe.a == int((step / 25) % 2));
        CHECK(t.keyframe.w == Approx(double(step % 25) / 25).margin(1e-9));
        switches += step % 25 == 0;
        CHECK(t.bloodVolume == Approx(serial->stats().bloodVolume).epsilon(1e-12));
        CHECK(t.cavityVolume == Approx(serial->stats().cavityVolume).epsilon(1e-12));
        CHECK(t.particles == double(serial->particles().size()));
    }
    CHECK(switches == 5);
    const core::Totals t = run.totals();
    CHECK(t.bloodCount == Approx(serial->stats().blood.count));
    CHECK(t.bloodMv2 == Approx(serial->stats().blood.mv2).epsilon(1e-6));
    CHECK(t.virialVolume == Approx(serial->stats().forces.virialVolume).epsilon(1e-6).margin(1e-9));
    CHECK(t.wallVirial == Approx(serial->stats().forces.wallVirial).epsilon(1e-6));
    REQUIRE(serial->construction().totals().births > 20);  // the bag grew under the moving map
    const core::Particles got = run.gather();
    const core::Particles& want = serial->particles();
    std::map<std::uint64_t, std::size_t> at;
    for (std::size_t i = 0; i < want.size(); ++i) at[want.id[i]] = i;
    REQUIRE(got.size() == want.size());
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const auto it = at.find(got.id[i]);
        REQUIRE(it != at.end());
        worst = std::max(worst, (got.pos[i] - want.pos[it->second]).norm());
    }
    INFO("largest position difference " << worst);
    CHECK(worst < 1e-8);
}

TEST_CASE("bop-server's start under mpirun reads every keyframe's window from the cache file", "[mpi][keyframes]") {
    // One scene and one cache for all ranks (the cache's key is the scene's text, paths included).
    const std::string dir = "/tmp/bop-mpi-keyframes-np" + std::to_string(parallel::MpiSession::worldSize());
    const bool root = parallel::MpiSession::worldRank() == 0;
    if (root) {
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
        test::writeKeyframeScene(dir, 0.5, true, test::kGrowFromSeeds);
    }
    parallel::MpiSession::barrier();
    app::Scene s = app::loadScene(dir + "/keyframes.toml");
    app::RunStart start = app::startRun(s, dir + "/map.bopgm", "", root, parallel::MpiSession::barrier);
    REQUIRE(start.options.map);
    CHECK(start.options.map->frames == 2);
    app::Scene serialScene = app::loadScene(dir + "/keyframes.toml");
    test::OneProcessRun serial(serialScene);
    const CartComm comm(MPI_COMM_WORLD, start.model->box);
    RankRun run(start.model, start.particles, std::move(start.options));
    for (long long step = 1; step <= 60; ++step) {
        serial->step();
        run.step();
        const core::Totals t = run.totals();
        INFO("step " << step);
        CHECK(t.keyframe.a == int((step / 25) % 2));
        CHECK(t.cavityVolume == Approx(serial->stats().cavityVolume).epsilon(1e-12));
        CHECK(t.particles == double(serial->particles().size()));
    }
    CHECK(run.totals().wallVirial == Approx(serial->stats().forces.wallVirial).epsilon(1e-6));
    parallel::MpiSession::barrier();
    if (root) std::filesystem::remove_all(dir);
}
