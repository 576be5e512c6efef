// libFuzzer target "front": message sequences through the real server, not only its decoders.
// Messages go into a live ServerFront (ServerFront::inject: the same checks, sessions, refusals
// and answers as messages off its socket, from four peers), and passes of the served run's loop
// (app/ServedLoop.hpp) between them take the commands and probes, apply them to a decomposed run
// of a small bag (one rank), step it, and offer feedback and frames to the front's threads.
//
// An input is a sequence of records: one byte `op`, then for a message two bytes of length
// (little-endian, cut to what is left) and the message. op % 4 = 0 or 1: a message from peer
// (op / 4) % 4; 2 or 3: 1 + (op / 4) % 8 passes of the loop. At most 16 passes an input. Every
// input starts from the same built bag (the run is reseated after an input that stepped it or
// left commands queued in it), paused, with a fresh controls, the scene's probe and nothing queued
// in the front; the front's sessions go on. One thread: a campaign runs on one core.
//
// The contract, beyond the sanitizers': nothing thrown leaves the loop (no UnsoundState: no
// in-range input may make the physics unsound), the front counts no internal error, and the
// run's totals stay finite.
#include "app/runs/ServedLoop.hpp"
#include "app/runs/ServedRun.hpp"
#include "app/scene/RunStart.hpp"
#include "app/scene/SceneConfig.hpp"
#include "core/Run.hpp"
#include "core/Threads.hpp"
#include "parallel/Session.hpp"
#include "server/ServerFront.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <unistd.h>

namespace {

using namespace bop;

// A sphere bag of about 30 particles (two species), built by its construction timeline: small,
// so that the steps cost little beside the handling the fuzzer is after.
constexpr const char* kScene = R"(
[grid]
voxel_size_mm = 1.0
padding_voxels = 3
r0_voxels = 2.0
[shape]
[[shape.bag]]
name = "ball"
source = "sphere"
radius_mm = 2.5
[dynamics]
time_step = 0.02
[construction]
every_steps = 10
[[construction.event]]
step = 0
action = "seed"
species = 1
[[construction.event]]
step = 0
action = "birth_on"
species = 1
[[construction.event]]
step = 150
action = "seed"
species = 2
[[construction.event]]
step = 150
action = "birth_on"
species = 2
[interactions]
co_normal = [[0.3, 0.0], [0.0, 0.0]]
co_planar = [[0.3, 0.0], [0.0, 0.0]]
)";
constexpr long long kBuildSteps = 300;
constexpr int kMaxPasses = 16;

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "\nFUZZ CONTRACT BROKEN (front): %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

struct World {
    std::string dir;
    std::unique_ptr<parallel::MpiSession> mpi;
    app::Scene scene;
    std::unique_ptr<core::Run> run;
    core::Particles built;
    std::unique_ptr<core::Construction> construction;
    long long builtStep = 0;
    std::unique_ptr<protocol::ServerFront> front;
    app::ServeOptions serve;
};
World* gWorld = nullptr;

void setUp(int* argc, char*** argv) {
    auto* w = new World;
    char pattern[] = "/tmp/bop-fuzz-front-XXXXXX";
    if (!mkdtemp(pattern)) fail("cannot make a temporary folder");
    w->dir = pattern;
    w->mpi = std::make_unique<parallel::MpiSession>(*argc, *argv);
    core::setThreadCount(1);
    const std::string path = w->dir + "/ball.toml";
    std::ofstream(path) << kScene;
    w->scene = app::loadScene(path);
    app::RunStart start = app::startRun(w->scene, w->dir + "/ball.bopgm", "", true, parallel::MpiSession::barrier);
    w->run = std::make_unique<core::Run>(start.model, start.particles, std::move(start.options));
    w->run->setProbe(start.probe);
    w->run->setEnergyEvery(1);
    for (long long s = 0; s < kBuildSteps; ++s) w->run->step();
    w->built = w->run->gather();
    w->construction = std::make_unique<core::Construction>(w->run->construction());
    w->builtStep = w->run->stepNumber();
    protocol::FrontOptions o;
    o.basePort = 0;
    o.mapFile = w->dir + "/ball.bopgm";
    protocol::SceneInfo info = app::sceneInfoOf(w->scene, w->run->simulation().model(), nullptr);
    info.mapBytes = std::filesystem::file_size(o.mapFile);
    w->front = std::make_unique<protocol::ServerFront>(o, info);
    w->serve.front = o;
    // The loop refuses clients' Record commands while "the operator records" (the front itself
    // records nothing): a fuzzer must not write files.
    w->serve.front.recordPath = w->dir + "/operator.mcap";
    w->serve.outDir = w->dir;
    std::fprintf(stderr, "front fuzzer: a bag of %zu particles built in %lld steps; front on %s\n", w->built.size(),
                 kBuildSteps, w->front->controlEndpoint().c_str());
    gWorld = w;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
    setUp(argc, argv);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    World& w = *gWorld;
    if (w.run->stepNumber() != w.builtStep || w.run->commandsQueued())
        w.run->reseat(w.built, *w.construction, w.builtStep);
    w.run->setProbe(w.scene.probe);
    w.front->takeCommands();  // what an earlier input left queued
    w.front->takeProbe();
    app::ServedLoop loop(
        w.scene, *w.run, w.front.get(), w.serve, [] { return false; }, {},
        std::chrono::microseconds(0));  // a paused pass does not wait
    // Paused, as a client may leave a server: the run steps only when the input resumes it or
    // asks for single steps, so that an input's cost lies in its messages, not in the physics.
    loop.controls().paused = true;
    const std::uint64_t errorsBefore = w.front->stats().internalErrors;
    int passes = 0;
    const auto pass = [&] {
        if (passes++ >= kMaxPasses) return;
        try {
            if (!loop.pass()) fail("the loop stopped: " + loop.error());
        } catch (const core::UnsoundState& e) {
            fail(std::string("in-range input made the run unsound: ") + e.what());
        } catch (const std::exception& e) {
            fail(std::string("thrown out of the loop: ") + e.what());
        }
    };
    for (std::size_t k = 0; k < size;) {
        const std::uint8_t op = data[k++];
        switch (op % 4) {
            case 0:
            case 1: {
                std::size_t n = 0;
                if (k < size) n = data[k++];
                if (k < size) n |= std::size_t(data[k++]) << 8;
                n = std::min(n, size - k);
                w.front->inject("peer" + std::to_string((op / 4) % 4), data + k, n);
                k += n;
                break;
            }
            default:
                for (int p = 0; p <= (op / 4) % 8; ++p) pass();
        }
    }
    const core::Totals t = w.run->totals();
    if (!(std::isfinite(t.kinetic) && std::isfinite(t.pairEnergy) && t.probeReaction.allFinite()))
        fail("the run's totals are not finite");
    if (w.front->stats().internalErrors != errorsBefore)
        fail("internal error in the front: " + w.front->stats().lastInternalError);
    return 0;
}
