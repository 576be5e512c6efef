#include "app/runs/DecomposedBatch.hpp"

#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/BatchReport.hpp"
#include "app/runs/ExitCodes.hpp"
#include "app/runs/SingleBatch.hpp"
#include "app/scene/SimulationSetup.hpp"
#include "bop/common/GradientMapFile.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>

namespace fs = std::filesystem;

namespace bop::app {

void recordCardiac(CardiacRun& cardiac, parallel::DecomposedRun& run, const core::Model& model) {
    const parallel::Totals t = run.totals();
    const long long step = run.stepNumber();
    if (cardiac.wantsParticles(step)) {
        const core::Particles all = run.gather();
        if (run.rank() == 0) cardiac.particles(model, all);
    }
    cardiac.step({step, double(step) * model.integration.dt, t.keyframe, t.bloodMv2, t.virialVolume, t.wallVirial,
                  t.bloodCount, t.bloodVolume, t.cavityVolume});
}

int runDecomposedBatch(const Scene& scene, DecomposedStart start, const BatchOptions& o) {
    const core::Model& model = *scene.model;
    const long long firstStep = start.firstStep;
    const std::optional<GradientMap> header =
        start.options.map ? std::optional(start.options.map->header) : std::nullopt;
    parallel::DecomposedRun run(scene.model, start.particles, std::move(start.options));
    start.particles = {};
    run.setProbe(scene.probe);
    run.refreshForces();
    const bool root = run.rank() == 0;
    const auto dims = run.dims();
    const parallel::RunCounters c0 = run.counters();
    spdlog::info(
        "decomposed over {} ranks, grid {} x {} x {}; particles per rank max/mean {:.3f} with uniform cuts, "
        "{:.3f} balanced",
        run.size(), dims[0], dims[1], dims[2], c0.initialImbalance, c0.imbalance);
    if (c0.mapBytesMax > 0)
        spdlog::info("gradient map: at most {:.3f} MB per rank (its subdomain's window)", c0.mapBytesMax / 1e6);
    run.setEnergyEvery(std::numeric_limits<long long>::max());
    const std::vector<std::string> names = speciesNames(model);
    const std::string trajectory = o.outDir + "/trajectory.xyz";
    if (root && o.snapshotEvery > 0) fs::remove(trajectory);
    auto write = [&](const std::string& path, const core::Particles& all, long long step) {
        appendExtendedXyz(path, all, names, snapshotInfo(model, step));
    };
    std::optional<CardiacRun> cardiac;
    if (scene.pressure && header) cardiac.emplace(scene, *header, run.frameVolumes());
    const std::string checkpoint = o.outDir + "/checkpoint.xyz";
    long long done = 0;
    bool stopped = false;
    if (o.steps == 0) {  // nothing to step: the start itself is the checkpoint
        const core::Particles all = run.gather();
        if (root) writeCheckpoint(checkpoint, all, model, run.construction(), run.stepNumber());
    }
    installBatchSignals();  // from here a signal ends the run with a checkpoint
    const auto t0 = std::chrono::steady_clock::now();
    for (long long s = 1; s <= o.steps; ++s) {
        try {
            run.step();
        } catch (const core::UnsoundState& e) {                               // on every rank
            const std::optional<core::SoundSnapshot> last = run.lastSound();  // collective
            return root ? stopUnsound(e, last, model, checkpoint, o.outDir) : kExitUnsound;
        }
        done = s;
        if (cardiac) recordCardiac(*cardiac, run, model);
        // Periods count absolute steps, so that a restarted run reports where the run did.
        if (o.snapshotEvery > 0 && (firstStep + s) % o.snapshotEvery == 0) {
            const core::Particles all = run.gather();  // collective
            if (root) write(trajectory, all, firstStep + s);
        }
        if ((firstStep + s) % o.reportEvery == 0 || s == o.steps) {
            run.refreshForces();  // the same forces again, now with the energies
            const parallel::Totals t = run.totals();
            const parallel::RunCounters c = run.counters();
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (root)
                std::cout << std::fixed << std::setprecision(1) << "step " << firstStep + s << " ("
                          << 100.0 * double(s) / double(o.steps) << "%)  particles " << t.particles << "  E_kin "
                          << std::setprecision(4) << t.kinetic << "  E_pair " << t.pairEnergy << "  "
                          << std::setprecision(1) << double(s) / std::max(elapsed, 1e-9) << " steps/s" << std::endl;
            if (root && (c.births > 0 || c.deaths > 0))
                std::cout << "  construction so far: " << std::setprecision(0) << c.births << " births, " << c.deaths
                          << " deaths\n";
        }
        // Rank 0's signal decides for every rank (mpirun passes SIGTERM to them all, not at once).
        stopped = run.agree({batchStopRequested() ? 1 : 0}).stop != 0;
        const long long step = run.stepNumber();
        const bool last = stopped || s == o.steps;
        if ((o.checkpointEvery > 0 && step % o.checkpointEvery == 0) || last) {
            const core::Particles all = run.gather();  // collective: every particle on every rank, by id
            if (root) writeCheckpoint(checkpoint, all, model, run.construction(), step);
            if (last) break;
            // Go on from it as a restart from the file would (the same decomposition and lists): the
            // gathered values are the file's (%.17g reads back exactly), so no rank reads the file.
            core::Construction construction(scene.construction, scene.timeline, model.speciesCount());
            construction.restore(
                {run.construction().birthSwitches().begin() + 1, run.construction().birthSwitches().end()},
                run.construction().seedCount());
            construction.addToTotals(run.construction().totals());
            run.reseat(all, construction, step);
            run.refreshForces();
        }
    }
    if (stopped) {
        run.refreshForces();  // the summary's energies of this state
        if (root)
            std::cout << "stopped by a signal after step " << firstStep + done << "; checkpoint: " << checkpoint
                      << std::endl;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const parallel::Totals t = run.totals();
    const parallel::RunCounters c = run.counters();
    const core::Particles all = run.gather();  // collective
    if (!root) return 0;
    const std::string finalFile = o.outDir + "/final.xyz";
    fs::remove(finalFile);
    write(finalFile, all, firstStep + done);
    const auto [surface, volume] = countKinds(model, all);
    const double rate = double(done) / std::max(seconds, 1e-12);
    std::cout << "\n            Surface  Volume   Total   steps/s   particle-steps/s\n"
              << "this run  " << std::setw(9) << surface << std::setw(8) << volume << std::setw(8) << surface + volume
              << std::setw(10) << std::setprecision(1) << rate << std::setw(19) << std::setprecision(0)
              << rate * double(surface + volume) << "\n"
              << run.size() << " ranks: halo " << std::setprecision(0) << c.haloBytesPerStep
              << " bytes per step, particles per rank max/mean " << std::setprecision(3) << c.imbalance << ", "
              << std::setprecision(0) << c.rebuilds << " rebuilds, " << c.rebalances << " balancings, " << c.migrations
              << " migrations; exchanges took " << std::setprecision(1)
              << 100.0 * c.exchangeSecondsMax / std::max(seconds, 1e-12) << "% of the run on the busiest rank\n"
              << "E_kin " << std::setprecision(5) << t.kinetic << ", E_pair " << t.pairEnergy << ", virial " << t.virial
              << "\n";
    if (c.mapBytesMax > 0)
        std::cout << "gradient map: at most " << std::setprecision(3) << c.mapBytesMax / 1e6 << " MB per rank\n";
    if (c.births > 0 || c.deaths > 0)
        std::cout << "construction: " << std::setprecision(0) << c.births << " births, " << c.deaths << " deaths\n";
    if (scene.shape && !o.cache.empty())
        if (auto maps = bop::readGradientMaps(o.cache, bop::hashText(scene.shape->canonical))) {
            core::Model whole = model;
            whole.map =
                std::make_shared<GradientMap>(std::move(maps->at(std::size_t(t.keyframe.a))));  // the frame in force
            printFidelity(std::cout, measureFidelity(whole, all));
        }
    if (cardiac) cardiac->finish(o.outDir, std::cout);
    spdlog::info("final state: {}{}", finalFile, o.snapshotEvery > 0 ? ", trajectory: " + trajectory : "");
    return 0;
}

}  // namespace bop::app
