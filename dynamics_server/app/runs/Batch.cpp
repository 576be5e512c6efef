#include "app/runs/Batch.hpp"

#include "app/cardiac/CardiacRun.hpp"
#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/BatchReport.hpp"
#include "app/runs/ExitCodes.hpp"
#include "app/runs/Settling.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "shape/GradientMapFileView.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>

namespace fs = std::filesystem;

namespace bop::app {
namespace {

volatile std::sig_atomic_t gStop = 0;
void onSignal(int sig) {
    if (gStop) {  // a second signal: no more waiting for the step in progress
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
    gStop = 1;
}

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The map and shape fidelity lines of the summary (rank 0): `mapBytes` the largest window one
// process holds; the fidelity against the whole map of `frame`, the frame in force, read from
// the cache.
void printMap(const Scene& scene, const core::Run& run, double mapBytes, int frame, const core::Particles& all,
              const std::string& cache) {
    if (mapBytes > 0) {
        std::cout << "gradient map: " << std::fixed << std::setprecision(3);
        if (run.size() == 1)
            std::cout << mapBytes / 1e6 << " MB (the whole map"
                      << (run.frameVolumes().size() > 1 ? ", every keyframe" : "") << ", one process)\n";
        else
            std::cout << "at most " << mapBytes / 1e6 << " MB per rank\n";
        std::cout << std::defaultfloat;
    }
    if (!scene.shape || cache.empty()) return;
    const auto view = shape::GradientMapFileView::open(cache, bop::hashText(scene.shape->canonical));
    if (!view) return;
    const GradientMap header = view->header(frame);
    core::Model whole = *scene.model;
    whole.map = std::make_shared<GradientMap>(view->crop(
        frame, bop::VoxelWindow{Eigen::Vector3i::Zero(),
                                Eigen::Vector3i(header.wholeDims().nx, header.wholeDims().ny, header.wholeDims().nz)}));
    printFidelity(std::cout, measureFidelity(whole, all));
}

}  // namespace

void installBatchSignals() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::signal(SIGUSR1, onSignal);  // mpirun passes it to the ranks without killing them after 1 s
}

bool batchStopRequested() {
    return gStop != 0;
}

int stopUnsound(const core::UnsoundState& e, const std::optional<core::SoundSnapshot>& last, const core::Model& model,
                const std::string& checkpoint, const std::string& outDir) {
    fs::remove(outDir + "/final.xyz");  // no final state: it would hold NaN or a runaway
    spdlog::error("stopped: {}", e.what());
    if (!last) {
        spdlog::error("the run's start was not sound: no checkpoint written");
        return kExitUnsound;
    }
    writeCheckpoint(checkpoint, last->particles, model, last->construction, last->step);
    spdlog::error("the last sound state (step {}) is in {}", last->step, checkpoint);
    return kExitUnsound;
}

int runBatch(const Scene& scene, RunStart start, const BatchOptions& o, core::ExchangeMaker exchanges) {
    const auto t00 = std::chrono::steady_clock::now();
    const core::Model& model = *scene.model;
    const std::optional<GradientMap> header =
        start.options.map ? std::optional(start.options.map->header) : std::nullopt;
    core::Run run(scene.model, start.particles, std::move(start.options), std::move(exchanges));
    start.particles = {};
    run.setProbe(scene.probe);
    run.refreshForces();  // set-up: with the probe, outside the timed steps
    run.resetTimes();
    const bool root = run.rank() == 0;
    const double particles = run.totals().particles;
    spdlog::info("ready in {:.2f} s: {} particles at step {}", secondsSince(t00), particles, run.stepNumber());
    if (run.size() > 1) {
        const auto grid = run.grid();
        const core::RunCounters c0 = run.counters();
        spdlog::info(
            "decomposed over {} ranks, grid {} x {} x {}; particles per rank max/mean {:.3f} with uniform cuts, "
            "{:.3f} balanced",
            run.size(), grid[0], grid[1], grid[2], c0.initialImbalance, c0.imbalance);
        if (c0.mapBytesMax > 0)
            spdlog::info("gradient map: at most {:.3f} MB per rank (its subdomain's window)", c0.mapBytesMax / 1e6);
    }
    run.setEnergyEvery(std::numeric_limits<long long>::max());  // energies only for the reports below
    const std::vector<std::string> names = speciesNames(model);
    const std::string trajectory = o.outDir + "/trajectory.xyz", checkpoint = o.outDir + "/checkpoint.xyz";
    if (root && o.snapshotEvery > 0) fs::remove(trajectory);
    const auto write = [&](const std::string& path, const core::Particles& all) {
        appendExtendedXyz(path, all, names, snapshotInfo(model, run.stepNumber()));
    };
    // A checkpoint of every particle (by id), and the run goes on from it exactly as a restart
    // from the file would: the gathered values are the file's (%.17g reads back exactly).
    std::optional<core::Particles> lastState;  // the last checkpoint's particles: the final state's too
    std::optional<Settling> settling;          // a placed bag's, with its state in the checkpoints
    if (o.settle) settling.emplace(run, *o.settle, start.settle, start.settleFile);
    const auto takeCheckpoint = [&](bool goOn) {
        core::Particles all = run.gather();
        if (root)
            writeCheckpoint(checkpoint, all, model, run.construction(), run.stepNumber(),
                            settling ? settling->state(run) : std::string());
        if (!goOn) {  // the run ends here: its final state is these particles (forces are not written)
            lastState = std::move(all);
            return;
        }
        core::Construction construction(scene.construction, scene.timeline, model.speciesCount());
        construction.restore({run.construction().birthSwitches().begin() + 1, run.construction().birthSwitches().end()},
                             run.construction().seedCount(), run.construction().nextId());
        construction.addToTotals(run.construction().totals());  // the run's births and deaths so far
        run.reseat(all, construction, run.stepNumber());
        run.refreshForces();
    };
    BatchReport report(std::cout, run);
    std::optional<CardiacRun> cardiac;
    if (scene.pressure && header) cardiac.emplace(scene, *header, run.frameVolumes());
    long long done = 0;
    bool stopped = false, settled = false;
    double lastSettleLine = 0;                // wall time of the last settling line, s since t0
    if (o.steps == 0) takeCheckpoint(false);  // nothing to step: the start itself is the checkpoint
    installBatchSignals();                    // from here a signal ends the run with a checkpoint
    const auto t0 = std::chrono::steady_clock::now();
    for (long long s = 1; s <= o.steps; ++s) {
        try {
            run.step();
        } catch (const core::UnsoundState& e) {                               // on every process
            const std::optional<core::SoundSnapshot> last = run.lastSound();  // collective
            return root ? stopUnsound(e, last, model, checkpoint, o.outDir) : kExitUnsound;
        }
        done = s;
        if (cardiac) cardiac->record(run, model);
        // Periods count absolute steps, so that a restarted run reports where the run did.
        const long long step = run.stepNumber();
        if (o.snapshotEvery > 0 && step % o.snapshotEvery == 0) {
            const core::Particles all = run.gather();
            if (root) write(trajectory, all);
        }
        if (step % o.reportEvery == 0 || s == o.steps) {
            run.refreshForces();  // the same forces again, now with the energies
            report.progress(s, o.steps, t0);
        }
        // Rank 0's signal decides for every rank (mpirun passes SIGTERM to them all, not at once).
        stopped = run.agree({batchStopRequested() ? 1 : 0}).stop != 0;
        if (settling && !settled) {
            const bool minimising = run.minimising();
            settled = settling->afterStep(run);
            // Settling shows its progress: at most one line every 2 s of wall time.
            const double now = secondsSince(t0);
            const RunSettings& r = *o.settle;
            if (!settled && root && now >= lastSettleLine + 2.0 && step % settling->everySteps() == 0) {
                lastSettleLine = now;
                std::cout << "settling" << (minimising ? " (FIRE)" : "") << ": step " << step << ", kinetic energy "
                          << std::scientific << std::setprecision(2) << settling->lastPerParticle()
                          << " per particle (settled at " << r.settleKinetic << " over " << r.settleCalmSteps
                          << " steps), " << std::defaultfloat << std::setprecision(3) << double(s) / now << " steps/s"
                          << std::setprecision(6) << std::endl;
            }
            if (settled && root)
                std::cout << "settled at step " << step << ": kinetic energy " << std::scientific
                          << std::setprecision(2) << settling->lastPerParticle() << " per particle (at most "
                          << r.settleKinetic << " at every check over " << r.settleCalmSteps << " steps, "
                          << r.settleEverySteps << " steps apart)" << std::defaultfloat << std::setprecision(6)
                          << (settling->minimiserSteps() > 0
                                  ? "; the FIRE minimiser's first " + std::to_string(settling->minimiserSteps()) +
                                        " steps, then the damped dynamics"
                                  : "")
                          << std::endl;
        }
        const bool last = stopped || settled || s == o.steps;
        if ((o.checkpointEvery > 0 && step % o.checkpointEvery == 0) || last) takeCheckpoint(!last);
        if (last) break;
    }
    if (settling && !settled && !stopped && root)
        std::cout << "not settled after " << done << " steps (the run's cap): the kinetic energy per particle "
                  << "stayed above " << std::scientific << std::setprecision(2) << o.settle->settleKinetic
                  << std::defaultfloat << std::setprecision(6) << std::endl;
    if (stopped || settled) run.refreshForces();  // the summary's energies of this state
    if (stopped) {
        if (root)
            std::cout << "stopped by a signal after step " << run.stepNumber() << "; checkpoint: " << checkpoint
                      << std::endl;
    }
    const double seconds = secondsSince(t0);
    const core::Particles all = lastState ? std::move(*lastState) : run.gather();
    const std::string finalFile = o.outDir + "/final.xyz";
    if (root) {
        fs::remove(finalFile);
        write(finalFile, all);
    }
    report.summary(done, seconds);
    const double mapBytes = run.counters().mapBytesMax;
    const int frame = run.totals().keyframe.a;
    if (root) printMap(scene, run, mapBytes, frame, all, o.cache);
    if (root && cardiac) cardiac->finish(o.outDir, std::cout);
    spdlog::info("final state: {}{}", finalFile, o.snapshotEvery > 0 ? ", trajectory: " + trajectory : "");
    if (root && cardiac) cardiac->plot(o.outDir, std::cout);
    return 0;
}

}  // namespace bop::app
