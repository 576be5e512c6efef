// bop-server SCENE.toml: the dynamics host. In batch mode (--steps K --no-listen) it builds or
// loads the scene's gradient map, places or reads the particles, runs K steps with the
// construction timeline, prints progress, per-phase timings and a Table-1 style summary, and
// writes extended XYZ snapshots. Under mpirun with more than one rank the run is decomposed
// over the ranks (core/Run.hpp over parallel/RankExchanges.hpp).
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/Batch.hpp"
#include "app/runs/ServedRun.hpp"
#include "app/scene/RunStart.hpp"
#include "app/scene/SceneConfig.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/ToolMain.hpp"
#include "core/TargetClones.hpp"
#include "core/Threads.hpp"
#include "parallel/RankExchanges.hpp"
#include "parallel/Session.hpp"
#include "security/CurveKeys.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <thread>

namespace fs = std::filesystem;
using namespace bop;

namespace {

int run(int argc, char** argv) {
    CLI::App app{
        "bop-server: the BoP dynamics host. Served: bop-server SCENE.toml [--port P] streams to viewers and "
        "haptic clients (docs/protocol.md) until SIGINT/SIGTERM or --steps K; batch: bop-server SCENE.toml "
        "--steps K --no-listen; under mpirun -np N the box is split into one subdomain per rank "
        "(docs/parallel.md)"};
    std::string scenePath, outDir, restart, cache, precision;
    long long steps = -1, snapshotEvery = -1, reportEvery = -1;
    int threads = 0;  // per rank; 0: chosen below
    bool noListen = false, waitForClient = false, readOnlyViewers = false, quantised = false;
    protocol::FrontOptions front;
    app.add_option("scene", scenePath, "scene file (TOML)")->required();
    app.add_option("--steps", steps, "steps to run (default: [run].steps of the scene)");
    app.add_flag("--no-listen", noListen, "batch run without the network front");
    app.add_option("-o,--out", outDir, "output folder (default: out/<scene name>)");
    app.add_option("--snapshot-every", snapshotEvery,
                   "extended XYZ snapshot period in steps (0 = only the final state)");
    app.add_option("--report-every", reportEvery, "progress line period in steps");
    app.add_option("--restart", restart,
                   "start from the last frame of an extended XYZ file (a checkpoint.xyz goes "
                   "on where its run stopped, at any rank count)");
    long long checkpointEvery = 0;
    app.add_option("--checkpoint-every", checkpointEvery,
                   "write <out>/checkpoint.xyz every N steps (0: only when "
                   "SIGINT/SIGTERM or --steps ends the run)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--cache", cache, "gradient-map cache (default: <out>/gradient-map.bopgm)");
    app.add_option("--port", front.basePort, "base port P: commands P, frames P+1, UDP probes P+2 (0 = ephemeral)")
        ->check(CLI::Range(0, 65533));
    app.add_option("--bind", front.bindAddress, "address to bind (default 127.0.0.1; * = every interface)");
    app.add_option("--publish-hz", front.publishHz, "state-frame rate, wall Hz (clients may ask for more)")
        ->check(CLI::Range(1.0, 1000.0));
    app.add_option("--chunk-bytes", front.chunkBytes, "largest state-frame chunk, bytes")
        ->check(CLI::Range(4096, 1 << 30));
    app.add_flag("--quantised", quantised, "16-bit state frames (positions against the box, octahedral normals)");
    bool compact = false;
    app.add_flag("--compact", compact,
                 "8 bytes a particle: positions as --quantised, normals octahedral in 8 bits a coordinate (0.95 deg), "
                 "species as runs")
        ->excludes("--quantised");
    app.add_flag("--frame-ids", front.frameIds, "state frames carry every particle's id (8 bytes per particle)");
    app.add_flag("--wait-for-client", waitForClient, "hold the first step until a client has said hello");
    app.add_flag("--read-only-viewers", readOnlyViewers, "viewers may watch but not command");
    app.add_option("--record", front.recordPath, "record the session (commands, probes, frames) as MCAP in this file");
    double sessionTimeout = 30;
    app.add_option("--session-timeout", sessionTimeout,
                   "forget a client's session after this many seconds without a "
                   "message from it (clients keep theirs alive; 0 = never)")
        ->check(CLI::Range(0.0, 86400.0));
    std::string replayInputs, curveSecret;
    app.add_option("--curve-secret", curveSecret,
                   "CURVE secret key file (bop-keys): encrypt every session; clients "
                   "need the matching public key");
    std::vector<std::string> curveClients;
    app.add_option("--curve-client", curveClients,
                   "a client's CURVE public key file (bop-keys PREFIX.pub); when "
                   "given, only clients holding one of these keys get in")
        ->check(CLI::ExistingFile);
    app.add_option("--threads", threads,
                   "threads per rank (default: OMP_NUM_THREADS, else this machine's cores shared among its ranks)")
        ->check(CLI::Range(0, 1024));
    app.add_option("--precision", precision,
                   "the LJ loop's pair arithmetic: double, or mixed (float lanes, double sums); default: the "
                   "scene's [dynamics] precision, else double")
        ->check(CLI::IsMember({"double", "mixed"}));
    app.add_option("--replay-inputs", replayInputs,
                   "apply a recorded session's commands and probes at their steps "
                   "instead of clients' (bop-replay check runs this)");
    CLI11_PARSE(app, argc, argv);
    front.frameEncoding = compact     ? protocol::FrameEncoding::Compact8
                          : quantised ? protocol::FrameEncoding::Quantised16
                                      : protocol::FrameEncoding::Float32;
    if (!std::isfinite(sessionTimeout) || (sessionTimeout != 0 && sessionTimeout < 0.5))
        throw Error("--session-timeout", "expected 0 (never) or 0.5 to 86400 seconds");
    front.sessionTimeout = std::chrono::milliseconds(std::llround(sessionTimeout * 1000));
    if (!curveSecret.empty()) front.curveSecretKey = protocol::readCurveKey(curveSecret);
    if (!curveClients.empty() && curveSecret.empty())
        throw Error("--curve-client", "needs --curve-secret: client keys are checked in CURVE handshakes");
    for (const std::string& f : curveClients) front.curveClientKeys.push_back(protocol::readCurveKey(f));
    front.viewersMayCommand = !readOnlyViewers;

    spdlog::set_pattern("[bop-server] %v");
    const int ranks = parallel::MpiSession::worldSize();
    if (parallel::MpiSession::worldRank() != 0) spdlog::set_level(spdlog::level::off);
    const int onNode = parallel::MpiSession::ranksOnThisNode();
    if (threads > 0) core::setThreadCount(threads);  // else MpiSession's choice
    spdlog::info("layout: {} rank{} x {} thread{} each ({} rank{} and {} cores on this machine); pair loops: {} clone",
                 ranks, ranks == 1 ? "" : "s", core::threadCount(), core::threadCount() == 1 ? "" : "s", onNode,
                 onNode == 1 ? "" : "s", std::thread::hardware_concurrency(), core::hotLoopClone());
    app::Scene scene = app::loadScene(scenePath);
    if (!precision.empty()) {  // over the scene's
        auto m = std::make_shared<core::Model>(*scene.model);
        m->integration.mixedPrecision = precision == "mixed";
        scene.model = std::move(m);
    }
    spdlog::info("pair arithmetic: {}", scene.model->integration.mixedPrecision
                                            ? "mixed (the pair loops in float lanes, sums in double)"
                                            : "double");
    if (scene.shape)
        for (const std::string& w : scene.shape->warnings) spdlog::warn("{}", w);
    if (scene.calibration)
        for (const std::string& line :
             app::calibrationReport(*scene.calibration, scene.materials, scene.model->integration.dt))
            spdlog::info("{}", line);
    else if (scene.shape)
        spdlog::info("units: length {:.4g} mm; mass, time and force in simulation units (no [[material]])",
                     scene.model->units.lengthMm);
    if (outDir.empty()) outDir = "out/" + fs::path(scenePath).stem().string();
    if (cache.empty()) cache = outDir + "/gradient-map.bopgm";
    fs::create_directories(outDir);
    const bool stepsGiven = steps >= 0;  // a served run without --steps runs until stopped
    if (steps < 0) steps = scene.run.steps;
    if (snapshotEvery < 0) snapshotEvery = scene.run.snapshotEverySteps;
    if (reportEvery < 0)
        reportEvery = scene.run.reportEverySteps > 0 ? scene.run.reportEverySteps : std::max(1LL, steps / 10);
    if (reportEvery == 0) throw Error("--report-every", "expected a period of at least 1 step");
    if (snapshotEvery < 0) throw Error("--snapshot-every", "expected 0 (final state only) or a period in steps");

    const core::Model& model = *scene.model;
    if (model.ljParams.mode == core::LjCutoff::Truncated)
        spdlog::warn("paper mode: LJ truncated at {} r0; bulk material collapses with this cutoff (docs/dynamics.md)",
                     model.ljParams.rCutR0);
    const auto progress = [](const std::string& m) { spdlog::info("{}", m); };
    // One start for every mode and rank count; one process exchanges nothing, ranks over MPI.
    app::RunStart start = app::startRun(scene, cache, restart, parallel::MpiSession::worldRank() == 0,
                                        parallel::MpiSession::barrier, progress);
    if (noListen && scene.run.untilSettled) {  // a batch run to the settled state steps at its own time step
        spdlog::info("until settled: time step {} (settle_time_step; [dynamics] time_step {})",
                     scene.run.settleTimeStep, scene.model->integration.dt);
        app::useSettleTimeStep(scene, start);
    }
    core::ExchangeMaker exchanges = ranks > 1 ? parallel::rankExchanges() : core::oneProcess();
    if (!noListen) {
        front.recordMeta = {{"scene", fs::absolute(scenePath).string()},
                            {"ranks", std::to_string(ranks)},
                            {"restart", restart},
                            {"precision", precision}};  // --precision's, if given (a replay gives it again)
        if (scene.shape) front.mapFile = cache;         // haptic clients download it (MapRequest)
        app::ServeOptions serve{front, stepsGiven ? steps : 0, waitForClient, outDir, std::nullopt, checkpointEvery};
        if (!replayInputs.empty()) serve.replay = protocol::readSession(replayInputs);
        return app::runServed(scene, std::move(start), serve, std::move(exchanges));
    }
    app::BatchOptions batch{steps, snapshotEvery, reportEvery, checkpointEvery, outDir, cache, std::nullopt};
    if (scene.run.untilSettled) batch.settle = scene.run;  // a placed bag: `steps` is then the cap
    return app::runBatch(scene, std::move(start), batch, std::move(exchanges));
}

}  // namespace

int main(int argc, char** argv) {
    bop::parallel::MpiSession mpi(argc, argv);
    const int code = bop::runTool("bop-server", [&] { return run(argc, argv); });
    // An error on one rank of several: end them all rather than leave them waiting. A run that
    // stopped on its own (kExitUnsound, kExitStoppedByError) ended on every rank alike.
    const bool together = code == bop::app::kExitUnsound || code == bop::app::kExitStoppedByError;
    if (code != 0 && !together && bop::parallel::MpiSession::worldSize() > 1) bop::parallel::MpiSession::abortAll(code);
    return code;
}
