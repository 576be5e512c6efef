#include "app/runs/SingleBatch.hpp"

#include "app/cardiac/CardiacRun.hpp"
#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/BatchReport.hpp"
#include "app/runs/ExitCodes.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "core/SoundState.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>

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

int runSingleBatch(Scene& scene, const std::string& restart, const BatchOptions& o, const shape::ProgressFn& progress) {
    const auto t00 = std::chrono::steady_clock::now();
    const core::Model& model = *scene.model;
    std::unique_ptr<core::Simulation> sim = startSimulation(scene, o.cache, restart, progress);
    sim->refreshForces();  // set-up: the first neighbour list and forces, outside the timed steps
    sim->resetTimes();
    spdlog::info("ready in {:.2f} s: {} particles at step {}",
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t00).count(), sim->particles().size(),
                 sim->stats().step);
    const std::vector<std::string> names = speciesNames(model);
    sim->setEnergyEvery(std::numeric_limits<long long>::max());  // energies only for the reports below
    const std::string trajectory = o.outDir + "/trajectory.xyz", checkpoint = o.outDir + "/checkpoint.xyz";
    if (o.snapshotEvery > 0) fs::remove(trajectory);
    auto snapshot = [&](const std::string& path) {
        appendExtendedXyz(path, sim->particles(), names, snapshotInfo(model, sim->stats().step));
    };
    // A checkpoint, and the run goes on from it exactly as a restart from the file would.
    auto takeCheckpoint = [&](bool goOn) {
        const long long step = sim->stats().step;
        writeCheckpoint(checkpoint, sim->particles(), model, sim->construction(), step);
        if (!goOn) return;
        const core::StepTimes times = sim->times();
        long long first = 0;
        core::Construction construction({}, {}, model.speciesCount());
        core::Particles p = initialParticles(scene, checkpoint, first, construction);
        construction.addToTotals(sim->construction().totals());  // the run's births and deaths so far
        const core::ProbeState probe = sim->probe();
        sim = std::make_unique<core::Simulation>(scene.model, std::move(p), std::move(construction), first);
        sim->probe() = probe;
        sim->refreshForces();
        sim->setTimes(times);
        sim->setEnergyEvery(std::numeric_limits<long long>::max());
    };
    BatchReport report(std::cout, model);
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<CardiacRun> cardiac;
    if (scene.pressure && sim->model().map) cardiac.emplace(scene, *sim->model().map, sim->frameVolumes());
    long long done = 0;
    bool stopped = false;
    if (o.steps == 0) takeCheckpoint(false);
    installBatchSignals();                     // from here a signal ends the run with a checkpoint
    std::optional<core::SoundSnapshot> sound;  // the last sound state (core/SoundState.hpp)
    const auto keep = [&] { sound = core::SoundSnapshot{sim->particles(), sim->construction(), sim->stats().step}; };
    if (core::sound(model, sim->particles(), sim->stats().forces.probeReaction)) keep();
    for (long long s = 1; s <= o.steps; ++s) {
        try {
            sim->step();
        } catch (const core::UnsoundState& e) {
            return stopUnsound(e, sound, model, checkpoint, o.outDir);
        }
        if (sim->stats().step % core::kSoundSnapshotEvery == 0) keep();
        done = s;
        if (cardiac) {
            const core::StepStats& st = sim->stats();
            if (cardiac->wantsParticles(st.step)) cardiac->particles(sim->model(), sim->particles());
            cardiac->step({st.step, double(st.step) * model.integration.dt, st.keyframe, st.blood.mv2,
                           st.forces.virialVolume, st.forces.wallVirial, st.blood.count, st.bloodVolume,
                           st.cavityVolume});
        }
        // Periods count absolute steps, so that a restarted run reports where the run did.
        const long long step = sim->stats().step;
        if (o.snapshotEvery > 0 && step % o.snapshotEvery == 0) snapshot(trajectory);
        if (step % o.reportEvery == 0 || s == o.steps) {
            sim->refreshForces();  // the same forces again, now with the energies
            report.progress(*sim, s, o.steps, t0);
        }
        stopped = batchStopRequested();
        const bool last = stopped || s == o.steps;
        if ((o.checkpointEvery > 0 && step % o.checkpointEvery == 0) || last) takeCheckpoint(!last);
        if (stopped) {
            spdlog::info("stopped by a signal after step {}; checkpoint: {}", step, checkpoint);
            sim->refreshForces();  // the summary's energies of this state
            break;
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string finalFile = o.outDir + "/final.xyz";
    fs::remove(finalFile);
    snapshot(finalFile);
    report.summary(*sim, done, seconds);
    if (model.map) {
        std::size_t bytes = 0;
        for (const auto& f : sim->model().frames) bytes += bop::gradientMapBytes(*f);
        if (bytes == 0) bytes = bop::gradientMapBytes(*model.map);
        std::cout << "gradient map: " << std::fixed << std::setprecision(3) << bytes / 1e6 << " MB (the whole map"
                  << (sim->model().frames.size() > 1 ? ", every keyframe" : "") << ", one process)\n"
                  << std::defaultfloat;
        printFidelity(std::cout, measureFidelity(sim->model(), sim->particles()));
    }
    if (cardiac) cardiac->finish(o.outDir, std::cout);
    spdlog::info("final state: {}{}", finalFile, o.snapshotEvery > 0 ? ", trajectory: " + trajectory : "");
    return 0;
}

}  // namespace bop::app
