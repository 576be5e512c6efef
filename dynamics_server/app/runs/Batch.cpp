#include "app/runs/Batch.hpp"

#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/BatchReport.hpp"
#include "app/runs/RunLifecycle.hpp"
#include "app/runs/Settling.hpp"
#include "app/scene/Fidelity.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "shape/GradientMapFileView.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>

namespace fs = std::filesystem;

namespace bop::app {
namespace {

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
    const GradientMap whole = view->crop(
        frame, bop::VoxelWindow{Eigen::Vector3i::Zero(),
                                Eigen::Vector3i(header.wholeDims().nx, header.wholeDims().ny, header.wholeDims().nz)});
    printFidelity(std::cout, measureFidelity(run.simulation().model(), whole, all));
}

void printSettling(const RunSettings& r, const Settling& settling, bool minimising, long long step, double rate) {
    std::cout << "settling" << (minimising ? " (FIRE)" : "") << ": step " << step << ", kinetic energy "
              << std::scientific << std::setprecision(2) << settling.lastPerParticle() << " per particle (settled at "
              << r.settleKinetic << " over " << r.settleCalmSteps << " steps), " << std::defaultfloat
              << std::setprecision(3) << rate << " steps/s" << std::setprecision(6) << std::endl;
}

void printSettled(const RunSettings& r, const Settling& settling, long long step) {
    std::cout << "settled at step " << step << ": kinetic energy " << std::scientific << std::setprecision(2)
              << settling.lastPerParticle() << " per particle (at most " << r.settleKinetic << " at every check over "
              << r.settleCalmSteps << " steps, " << r.settleEverySteps << " steps apart)" << std::defaultfloat
              << std::setprecision(6)
              << (settling.minimiserSteps() > 0
                      ? "; the FIRE minimiser's first " + std::to_string(settling.minimiserSteps()) +
                            " steps, then the damped dynamics"
                      : "")
              << std::endl;
}

}  // namespace

int runBatch(const Scene& scene, RunStart start, const BatchOptions& o, core::ExchangeMaker exchanges) {
    std::string settleFrom = std::move(start.settle), settleFile = std::move(start.settleFile);
    RunLifecycle life(scene, std::move(start), std::move(exchanges), {o.outDir, o.checkpointEvery});
    core::Run& run = life.run();
    const core::Model& model = life.model();
    const bool root = life.root();
    spdlog::info("ready in {:.2f} s: {} particles at step {}", life.readySeconds(), run.totals().particles,
                 run.stepNumber());
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
    const std::vector<std::string> names = speciesNames(model);
    const std::string trajectory = o.outDir + "/trajectory.xyz";
    if (root && o.snapshotEvery > 0) fs::remove(trajectory);
    std::optional<Settling> settling;  // a placed bag's, with its state in the checkpoints
    if (o.settle) {
        settling.emplace(run, *o.settle, settleFrom, settleFile);
        life.setCheckpointExtra([&] { return settling->state(run); });
    }
    BatchReport report(std::cout, run);
    long long done = 0;
    bool settled = false;
    double lastSettleLine = 0;  // wall time of the last settling line, s since t0
    installStopSignals();       // from here a signal ends the run with a checkpoint
    const auto t0 = std::chrono::steady_clock::now();
    // One step a pass, with the reports, snapshots and settling checks of its step.
    const auto pass = [&] {
        if (done >= o.steps) return false;
        run.step();
        const long long s = ++done;
        // Periods count absolute steps, so that a restarted run reports where the run did.
        const long long step = run.stepNumber();
        if (o.snapshotEvery > 0 && step % o.snapshotEvery == 0) {
            const core::Particles all = run.gather();
            if (root) appendExtendedXyz(trajectory, all, names, snapshotInfo(model, step));
        }
        if (step % o.reportEvery == 0 || s == o.steps) {
            run.refreshForces();  // the same forces again, now with the energies
            report.progress(s, o.steps, t0);
        }
        // Rank 0's signal decides for every rank (mpirun passes SIGTERM to them all, not at once).
        const bool stopped = run.agree({stopRequested() ? 1 : 0}).stop != 0;
        if (settling && !settled) {
            const bool minimising = run.minimising();
            settled = settling->afterStep(run);
            const double now = secondsSince(t0);
            if (root && !settled && now >= lastSettleLine + 2.0 && step % settling->everySteps() == 0) {
                lastSettleLine = now;  // settling shows its progress: at most one line every 2 s
                printSettling(*o.settle, *settling, minimising, step, double(s) / now);
            }
            if (root && settled) printSettled(*o.settle, *settling, step);
        }
        const bool last = stopped || settled || s == o.steps;
        life.afterStep(last);
        return !last;
    };
    const RunEnding end = life.drive(pass);
    if (end.code != 0) return end.code;
    if (settling && !settled && !stopRequested() && root)
        std::cout << "not settled after " << done << " steps (the run's cap): the kinetic energy per particle "
                  << "stayed above " << std::scientific << std::setprecision(2) << o.settle->settleKinetic
                  << std::defaultfloat << std::setprecision(6) << std::endl;
    if (stopRequested() || settled) run.refreshForces();  // the summary's energies of this state
    report.summary(done, secondsSince(t0));
    const double mapBytes = run.counters().mapBytesMax;
    const int frame = run.totals().keyframe.a;
    if (root) printMap(scene, run, mapBytes, frame, end.final, o.cache);
    if (root && life.cardiac()) life.cardiac()->finish(o.outDir, std::cout);
    spdlog::info("final state: {}{}", o.outDir + "/final.xyz",
                 o.snapshotEvery > 0 ? ", trajectory: " + trajectory : "");
    if (root && life.cardiac()) life.cardiac()->plot(o.outDir, std::cout);
    return 0;
}

}  // namespace bop::app
