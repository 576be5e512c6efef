// A served run's loop when rank 0's handling of its clients fails (an internal invariant broken,
// thrown inside the pass): every rank stops at the same pass, with the reason on rank 0, and the
// run's state is whole (what bop-server then writes as its checkpoint, exit code 4).
#include "RankRun.hpp"
#include "TestUtil.hpp"
#include "app/runs/ServedLoop.hpp"
#include "app/runs/ServedRun.hpp"
#include "app/scene/RunStart.hpp"
#include "parallel/Session.hpp"
#include "server/ServerFront.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <stdexcept>

using namespace bop;

TEST_CASE("an error inside rank 0's pass stops the served loop on every rank at that pass, its state whole",
          "[mpi][served]") {
    app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/bulk-box.toml");
    app::RunStart start =
        app::startRun(scene, "", "", parallel::MpiSession::worldRank() == 0, parallel::MpiSession::barrier);
    testing::RankRun run(start.model, start.particles, std::move(start.options));
    const std::size_t count = run.gather().size();
    REQUIRE(count > 1000);
    run.setProbe(scene.probe);
    run.refreshForces();
    const bool root = run.rank() == 0;
    app::ServeOptions serve;
    serve.front.basePort = 0;  // ephemeral ports on 127.0.0.1
    std::unique_ptr<protocol::ServerFront> front;
    if (root)
        front = std::make_unique<protocol::ServerFront>(serve.front, app::sceneInfoOf(scene, *start.model, nullptr));
    int asked = 0;
    const auto stopRequested = [&]() -> bool {
        if (++asked == 4) throw std::logic_error("an invariant broke");
        return false;
    };
    app::ServedLoop loop(scene, run, front.get(), serve, stopRequested, {}, std::chrono::microseconds(0));
    int passes = 0;
    while (loop.pass() && passes < 100) ++passes;
    CHECK(passes == 3);  // on every rank: the fourth pass stopped
    CHECK(loop.stepsDone() == 3);
    CHECK(run.stepNumber() == 3);
    if (root)
        CHECK(loop.error() == "taking the clients' inputs: an invariant broke");
    else
        CHECK(loop.error() == "rank 0 stopped the run");
    // The state is whole: every particle, every value finite, and the run can go on (collectives
    // still pair up on every rank).
    const core::Particles all = run.gather();
    CHECK(all.size() == count);
    bool finite = true;
    for (std::size_t i = 0; i < all.size(); ++i) finite = finite && all.pos[i].allFinite() && all.vel[i].allFinite();
    CHECK(finite);
    run.step();
    CHECK(run.stepNumber() == 4);
}
