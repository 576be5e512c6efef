#include "app/runs/ServedRun.hpp"

#include "app/runs/RunLifecycle.hpp"
#include "app/runs/ServedLoop.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "core/BloodPressure.hpp"
#include "core/Run.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

namespace bop::app {

protocol::SceneInfo sceneInfoOf(const Scene& scene, const core::Model& m, const GradientMap* map) {
    const core::Params& p = scene.params;
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
        s.tunables = {matrix(p.lj), matrix(p.coNormal), matrix(p.coPlanar), {}, {}, s.tunables.k0, s.tunables.k1};
    for (int k = 1; k <= n && std::size_t(n) <= protocol::kMaxTunedSpecies; ++k) {
        s.tunables.dragV.push_back(p.drag[std::size_t(k)].v);
        s.tunables.dragW.push_back(p.drag[std::size_t(k)].w);
    }
    const UnitSystem& u = scene.model->units;
    s.unitSystem = u;
    char words[240];
    if (u.physical)
        std::snprintf(words, sizeof words,
                      "length: %.6g mm per simulation unit (r0 = sqrt 3); time: %.6g s; force: %.6g N; mass %.6g kg "
                      "per particle",
                      u.lengthMm, u.timeS, u.forceN(), u.massKg);
    else if (u.lengthKnown())
        std::snprintf(words, sizeof words,
                      "length: %.6g mm per simulation unit (r0 = sqrt 3); time: simulation units; force: simulation "
                      "units; mass 1",
                      u.lengthMm);
    else
        std::snprintf(
            words, sizeof words,
            "length: simulation units (r0 = sqrt 3); time: simulation units; force: simulation units; mass 1");
    s.units = words;
    return s;
}

int runServed(const Scene& scene, RunStart start, const ServeOptions& o, core::ExchangeMaker exchanges) {
    const std::size_t particles = start.particles.size();
    RunLifecycle life(scene, std::move(start), std::move(exchanges), {o.outDir, o.checkpointEvery});
    core::Run& run = life.run();
    installStopSignals();
    std::unique_ptr<protocol::ServerFront> front;
    if (life.root()) {
        protocol::SceneInfo info = sceneInfoOf(scene, life.model(), life.mapHeader());
        info.particleCount = particles;
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
            while (!stopRequested() && !front->waitForClient(std::chrono::milliseconds(200))) {
            }
        }
    }
    ServedLoop loop(scene, run, front.get(), o, stopRequested, [&] { life.afterStep(); });
    const RunEnding end = life.drive([&] { return loop.pass(); }, [&] { return loop.error(); });
    if (!life.root()) return end.code;
    front->finish();  // the recording, if any, is complete from here
    const protocol::FrontStats s = front->stats();
    front.reset();
    if (!o.front.recordPath.empty())
        std::cout << (s.recordError.empty() ? "recorded the session in " + o.front.recordPath
                                            : "recording stopped early (" + s.recordError +
                                                  "); what was written is in " + o.front.recordPath + ".partial")
                  << "\n";
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
    if (const UnitSystem& u = scene.model->units; u.physical)
        std::cout << "simulated " << u.toS(double(loop.stepsDone()) * scene.model->integration.dt)
                  << " s at a real-time factor of " << loop.realTimeFactor() << " (simulated over wall seconds; "
                  << (scene.realTime ? "paced to the wall clock" : "[units] real_time = false: not paced") << ")\n";
    if (end.code == kExitUnsound) {
        spdlog::error("nothing unsound was streamed or recorded");
        return end.code;
    }
    if (life.cardiac()) life.cardiac()->finish(o.outDir, std::cout);
    spdlog::info("final state: {}; checkpoint: {}", o.outDir + "/final.xyz", o.outDir + "/checkpoint.xyz");
    // A signal may have stopped the run: mpirun is not waiting.
    if (life.cardiac()) life.cardiac()->plot(o.outDir, std::cout, true);
    return end.code;
}

}  // namespace bop::app
