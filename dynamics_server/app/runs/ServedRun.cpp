#include "app/runs/ServedRun.hpp"

#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/ServedLoop.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "core/BloodPressure.hpp"
#include "core/Run.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <filesystem>
#include <iostream>
#include <limits>
#include <thread>

namespace bop::app {
namespace {

using Clock = std::chrono::steady_clock;
volatile std::sig_atomic_t gStop = 0;
void onSignal(int) {
    gStop = 1;
}

}  // namespace

protocol::SceneInfo sceneInfoOf(const Scene& scene, const GradientMap* map) {
    const core::Model& m = *scene.model;
    protocol::SceneInfo s;
    for (int k = 1; k <= m.speciesCount(); ++k) {
        const core::Species& sp = m.species[std::size_t(k)];
        const auto c = [&](int a) { return std::uint8_t(std::lround(255 * sp.colour[std::size_t(a)])); };
        s.species.push_back({sp.name.substr(0, protocol::kMaxNameBytes),
                             m.isSurface(k) ? protocol::SpeciesKind::Surface : protocol::SpeciesKind::Volume,
                             {c(0), c(1), c(2), 255}});
    }
    s.boxLo = m.box.lo;
    s.boxHi = m.box.hi;
    if (map) {
        const Dims& d = map->wholeDims();
        s.gridOriginMm = map->grid.originMm;
        s.gridDims = {d.nx, d.ny, d.nz};
        s.voxelSizeMm = map->grid.voxelMm;
        s.r0Voxels = map->r0Voxels;
    }
    s.dt = m.integration.dt;
    s.probeReach = m.ljParams.rCutR0 * s.r0;
    const int n = m.speciesCount();
    const auto matrix = [&](const core::WeightMatrix& w) {
        std::vector<double> v;
        for (int a = 1; a <= n; ++a)
            for (int b = 1; b <= n; ++b) v.push_back(w(a, b));
        return v;
    };
    s.tunables.k0 = scene.probe.params.k0;
    s.tunables.k1 = scene.probe.params.k1;
    if (std::size_t(n) <= protocol::kMaxTunedSpecies)  // SceneInfo has a size cap
        s.tunables = {matrix(m.lj), matrix(m.coNormal), matrix(m.coPlanar), {}, {}, s.tunables.k0, s.tunables.k1};
    for (int k = 1; k <= n && std::size_t(n) <= protocol::kMaxTunedSpecies; ++k) {
        s.tunables.dragV.push_back(m.species[std::size_t(k)].dragV);
        s.tunables.dragW.push_back(m.species[std::size_t(k)].dragW);
    }
    s.units = "length: simulation units (r0 = sqrt 3); time: simulation units; force: simulation units; mass 1";
    return s;
}

int runServed(const Scene& scene, RunStart start, const ServeOptions& o, core::ExchangeMaker exchanges) {
    const core::Model& model = *scene.model;
    const GradientMap* header = start.options.map ? &start.options.map->header : nullptr;
    protocol::SceneInfo info = sceneInfoOf(scene, header);
    std::optional<CardiacRun> cardiac;  // [pressure]: the curve of a ventricle watched live, written at the end
    const std::optional<GradientMap> mapHeader = header ? std::optional(*header) : std::nullopt;
    core::Run run(scene.model, start.particles, std::move(start.options), std::move(exchanges));
    if (scene.pressure && mapHeader) cardiac.emplace(scene, *mapHeader, run.frameVolumes());
    const bool root = run.rank() == 0;
    run.setProbe(scene.probe);
    // Frames carry the energies: the steps that publish one compute them (ServedLoop), the others
    // do not.
    run.setEnergyEvery(std::numeric_limits<long long>::max());
    run.refreshForces();
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);

    std::unique_ptr<protocol::ServerFront> front;
    if (root) {
        info.particleCount = start.particles.size();
        std::error_code ec;  // the gradient-map cache, for haptic clients to download
        if (scene.shape && !o.front.mapFile.empty() && std::filesystem::is_regular_file(o.front.mapFile, ec)) {
            info.mapBytes = std::filesystem::file_size(o.front.mapFile, ec);
            info.mapKey = bop::hashText(scene.shape->canonical);
        }
        front = std::make_unique<protocol::ServerFront>(o.front, info);
        // Tests and scripts read this line for the ports.
        std::cout << "listening on " << front->controlEndpoint() << " (frames on port " << front->framePort() << ")"
                  << std::endl;
        if (o.waitForClient) {
            spdlog::info("waiting for a client (--wait-for-client)");
            while (!gStop && !front->waitForClient(std::chrono::milliseconds(200))) {
            }
        }
    }
    ServedLoop loop(
        scene, run, front.get(), o, [] { return gStop != 0; }, cardiac ? &*cardiac : nullptr);
    int code = 0;
    std::string why;
    try {
        while (loop.pass()) {
        }
        if (!loop.error().empty()) code = kExitStoppedByError, why = loop.error();
    } catch (const core::UnsoundState& e) {  // every rank, at the same step
        code = kExitUnsound, why = e.what();
    } catch (const std::exception& e) {
        if (run.size() > 1) throw;  // on this rank alone: the others cannot join a checkpoint (main aborts them all)
        code = kExitStoppedByError, why = e.what();
    }
    // Stopped by an unsound state: the last sound one is saved, and no final state (it holds NaN
    // or a runaway); otherwise the state now.
    const std::optional<core::SoundSnapshot> last = code == kExitUnsound ? run.lastSound() : std::nullopt;
    const core::Particles all = code == kExitUnsound ? core::Particles{} : run.gather();
    if (!root) return code;
    std::filesystem::create_directories(o.outDir);
    const std::string checkpoint = o.outDir + "/checkpoint.xyz", finalFile = o.outDir + "/final.xyz";
    if (code != kExitUnsound)
        writeCheckpoint(checkpoint, all, model, run.construction(), run.stepNumber());
    else if (last)
        writeCheckpoint(checkpoint, last->particles, model, last->construction, last->step);
    front->finish();  // the recording, if any, is complete from here
    const protocol::FrontStats s = front->stats();
    front.reset();
    if (!o.front.recordPath.empty())
        std::cout << (s.recordError.empty() ? "recorded the session in " + o.front.recordPath
                                            : "recording stopped early (" + s.recordError +
                                                  "); what was written is in " + o.front.recordPath + ".partial")
                  << "\n";
    std::filesystem::remove(finalFile);
    if (code != kExitUnsound)
        appendExtendedXyz(finalFile, all, speciesNames(model), snapshotInfo(model, run.stepNumber()));
    std::cout << "served " << loop.stepsDone() << " steps to " << s.sessionsOpened << " clients (" << s.sessionsExpired
              << " sessions expired, " << s.clients << " open at the end): " << s.framesSent << " frames ("
              << s.bytesSent / 1e6 << " MB, " << s.framesDropped << " replaced before sending), " << s.commands
              << " commands, " << s.probes << " probes, " << s.malformed << " malformed messages refused ("
              << s.oversized << " oversized), " << s.outOfRange << " messages with values out of range refused ("
              << s.refusalsSent << " refusals sent), " << s.peersRefused << " peers refused (CURVE key not allowed), "
              << s.internalErrors << " internal errors in the front"
              << (s.internalErrors ? " (last: " + s.lastInternalError + ")" : std::string())
              << "; the step loop waited on the front " << s.loopWaits << " times, longest " << s.loopWaitLongestMs
              << " ms, " << s.loopWaitTotalMs << " ms in all\n";
    if (cardiac && code != kExitUnsound) cardiac->finish(o.outDir, std::cout);
    if (code == kExitUnsound) {
        spdlog::error("stopped: {}", why);
        if (last)
            spdlog::error("the last sound state (step {}) is in {}; nothing unsound was streamed or recorded",
                          last->step, checkpoint);
        else
            spdlog::error("the run's start was not sound: no checkpoint written");
        return code;
    }
    if (code == kExitStoppedByError)
        spdlog::error("stopped by an error: {}; the state at step {} is in {}", why, run.stepNumber(), checkpoint);
    spdlog::info("final state: {}; checkpoint: {}", finalFile, checkpoint);
    if (cardiac) cardiac->plot(o.outDir, std::cout, true);  // a signal may have stopped the run: mpirun is not waiting
    return code;
}

}  // namespace bop::app
