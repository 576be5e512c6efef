#pragma once
// A run's lifecycle, one for the batch run (Batch.cpp) and the served one (ServedRun.cpp): the
// start (the run made over the exchanges, the scene's probe, the first forces), the one stop flag,
// the checkpoint policy, what an unsound state or an error leaves behind, and the final files.
// The two differ only in where their inputs come from and what each pass decides: the pass that
// drive() calls until it says stop.
//
// A checkpoint means the same in both: every particle by id in <out>/checkpoint.xyz (Checkpoint.hpp),
// and the run goes on from the file's values exactly as a restart from the file would (reseated).
// So a run stopped at any checkpoint and restarted from it gives the states the run that went on
// gave, at any rank count. (A checkpoint that only wrote the file would leave the run on values
// the file rounds, and the restarted run would part from it.)
#include "app/cardiac/CardiacRun.hpp"
#include "app/scene/RunStart.hpp"
#include "core/Run.hpp"

#include <chrono>
#include <functional>
#include <optional>
#include <string>

namespace bop::app {

// The one stop flag: SIGINT, SIGTERM or SIGUSR1 (mpirun passes it to the ranks without killing
// them after 1 s) set it once installStopSignals() ran; a second signal ends the process at once.
// Rank 0's flag decides for every rank, at a pass.
void installStopSignals();
bool stopRequested();

struct LifecycleOptions {
    std::string outDir;             // checkpoint.xyz and final.xyz go here
    long long checkpointEvery = 0;  // steps between checkpoints; one is always written when the run ends
};

// How a run ended: its exit code (0, kExitUnsound or kExitStoppedByError, ExitCodes.hpp), why,
// and its final state (every particle by id; empty after an unsound state).
struct RunEnding {
    int code = 0;
    std::string why;
    core::Particles final;
};

class RunLifecycle {
public:
    // Collective: every process calls it with the same scene and start.
    RunLifecycle(const Scene& scene, RunStart start, core::ExchangeMaker exchanges, LifecycleOptions o);

    core::Run& run() { return run_; }
    bool root() const { return run_.rank() == 0; }
    const Scene& scene() const { return scene_; }
    const core::Model& model() const { return *model_; }   // the start's (core::Run's)
    double readySeconds() const { return readySeconds_; }  // wall time from the start to the first forces
    CardiacRun* cardiac() { return cardiac_ ? &*cardiac_ : nullptr; }
    const GradientMap* mapHeader() const { return mapHeader_ ? &*mapHeader_ : nullptr; }
    // What a checkpoint keeps besides the particles (a settling's state, Settling.hpp).
    void setCheckpointExtra(std::function<std::string()> extra) { extra_ = std::move(extra); }

    // After each step: the ventricle's curve samples it, and the checkpoint when one is due
    // (`last`: the pass knows the run ends here, and the end writes it). Collective.
    void afterStep(bool last = false);
    // Calls `pass` until it returns false; a step that ends unsound, or an error (at one process;
    // at several, an error on one rank alone rethrows: the others cannot join a checkpoint) ends
    // it too. `error`, asked after the passes: why the pass stopped the run, empty if nothing went
    // wrong. Then the end's files: the checkpoint, and final.xyz (none after an unsound state,
    // whose checkpoint is the last sound state). Collective.
    RunEnding drive(const std::function<bool()>& pass, const std::function<std::string()>& error = {});

private:
    void checkpoint(const core::Particles& all, bool goOn);

    const Scene& scene_;
    std::shared_ptr<const core::Model> model_;       // the start's
    std::vector<core::ConstructionEvent> timeline_;  // the start's, for the construction a checkpoint restarts with
    std::chrono::steady_clock::time_point started_;
    std::optional<GradientMap> mapHeader_;
    core::Run run_;
    LifecycleOptions o_;
    std::optional<CardiacRun> cardiac_;
    std::function<std::string()> extra_;
    std::size_t cutsSaid_ = 0;  // cuts the log has told of
    double readySeconds_ = 0;
};

}  // namespace bop::app
