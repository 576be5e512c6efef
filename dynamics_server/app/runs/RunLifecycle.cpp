#include "app/runs/RunLifecycle.hpp"

#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/ExitCodes.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <filesystem>
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

}  // namespace

void installStopSignals() {
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::signal(SIGUSR1, onSignal);
}

bool stopRequested() {
    return gStop != 0;
}

RunLifecycle::RunLifecycle(const Scene& scene, RunStart start, core::ExchangeMaker exchanges, LifecycleOptions o)
    : scene_(scene),
      model_(start.model),
      timeline_(std::move(start.timeline)),
      started_(std::chrono::steady_clock::now()),
      mapHeader_(start.options.map ? std::optional(start.options.map->header) : std::nullopt),
      run_(model_, start.particles, std::move(start.options), std::move(exchanges)),
      o_(std::move(o)) {
    if (scene.pressure && mapHeader_) cardiac_.emplace(scene, *mapHeader_, run_.frameVolumes());
    run_.setProbe(start.probe);
    // Energies only where a report or a frame asks for them (the drivers' passes).
    run_.setEnergyEvery(std::numeric_limits<long long>::max());
    run_.refreshForces();  // set-up: with the probe, outside the timed steps
    run_.resetTimes();
    readySeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    if (root()) fs::create_directories(o_.outDir);
}

void RunLifecycle::checkpoint(const core::Particles& all, bool goOn) {
    const core::Model& model = *model_;
    if (root()) try {
            writeCheckpoint(o_.outDir + "/checkpoint.xyz", all, model, run_.construction(), run_.stepNumber(),
                            extra_ ? extra_() : std::string(), run_.simulation().cuts(), run_.simulation().yields());
        } catch (const std::exception& e) {  // on rank 0 alone: the run goes on; the previous checkpoint is whole
            spdlog::error("{}", e.what());
        }
    if (!goOn) return;
    // The run goes on from the file's values, with the construction a restart from it makes.
    core::Construction construction(scene_.construction, timeline_, model.speciesCount());
    construction.restore({run_.construction().birthSwitches().begin() + 1, run_.construction().birthSwitches().end()},
                         run_.construction().seedCount(), run_.construction().nextId());
    construction.addToTotals(run_.construction().totals());  // the run's births and deaths so far
    run_.reseat(all, construction, run_.stepNumber());
    run_.refreshForces();
}

void RunLifecycle::afterStep(bool last) {
    if (cardiac_) cardiac_->record(run_, *model_);
    if (const std::size_t cuts = run_.simulation().cutCommands(); cuts > cutsSaid_) {  // what the step's cut did
        cutsSaid_ = cuts;
        const core::CutReport& c = run_.simulation().lastCut();
        if (root() && c.refused)
            spdlog::warn("cut {} at step {} refused: it would take every voxel of every bag", cutsSaid_,
                         run_.stepNumber());
        else if (root())
            spdlog::info(
                "cut {} at step {}: {} particles out, {} made surface, {} bonds broken, {} bag(s); map "
                "edited in {:.2f} ms",
                cutsSaid_, run_.stepNumber(), c.removed, c.converted, c.bondsBroken, c.bags, 1e3 * c.mapSeconds);
    }
    if (!last && o_.checkpointEvery > 0 && run_.stepNumber() % o_.checkpointEvery == 0) checkpoint(run_.gather(), true);
}

RunEnding RunLifecycle::drive(const std::function<bool()>& pass, const std::function<std::string()>& error) {
    RunEnding end;
    try {
        while (pass()) {
        }
        if (error) end.why = error();
        if (!end.why.empty()) end.code = kExitStoppedByError;
    } catch (const core::UnsoundState& e) {  // every rank, at the same step
        end.code = kExitUnsound, end.why = e.what();
    } catch (const std::exception& e) {
        if (run_.size() > 1) throw;  // on this rank alone: the others cannot join a checkpoint (main aborts them all)
        end.code = kExitStoppedByError, end.why = e.what();
    }
    const std::string checkpointFile = o_.outDir + "/checkpoint.xyz", finalFile = o_.outDir + "/final.xyz";
    if (end.code == kExitUnsound) {
        const std::optional<core::SoundSnapshot> last = run_.lastSound();  // collective
        if (!root()) return end;
        fs::remove(finalFile);  // no final state: it would hold NaN or a runaway
        spdlog::error("stopped: {}", end.why);
        if (!last) {
            spdlog::error("the run's start was not sound: no checkpoint written");
            return end;
        }
        writeCheckpoint(checkpointFile, last->particles, *model_, last->construction, last->step, {},
                        run_.simulation().cuts(), run_.simulation().yields());
        spdlog::error("the last sound state (step {}) is in {}", last->step, checkpointFile);
        return end;
    }
    end.final = run_.gather();  // collective
    checkpoint(end.final, false);
    if (!root()) return end;
    fs::remove(finalFile);
    appendExtendedXyz(finalFile, end.final, speciesNames(*model_), snapshotInfo(*model_, run_.stepNumber()));
    if (end.code == kExitStoppedByError)
        spdlog::error("stopped by an error: {}; the state at step {} is in {}", end.why, run_.stepNumber(),
                      checkpointFile);
    else if (stopRequested())
        spdlog::info("stopped by a signal after step {}; checkpoint: {}", run_.stepNumber(), checkpointFile);
    return end;
}

}  // namespace bop::app
