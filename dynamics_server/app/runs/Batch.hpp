#pragma once
// bop-server's batch run (--no-listen), at one process or N ranks alike: core::Run stepped with
// progress reports, snapshots, checkpoints (every `checkpointEvery` steps and on SIGINT, SIGTERM
// or SIGUSR1, app/files/Checkpoint.hpp), the ventricle's pressure series when the scene asks for
// it, and the Table-1 style summary (BatchReport.hpp). Rank 0 writes the files.
#include "app/scene/SimulationSetup.hpp"
#include "core/Run.hpp"
#include "core/SoundState.hpp"

#include <optional>
#include <string>

namespace bop::app {

struct BatchOptions {
    long long steps = 0, snapshotEvery = 0, reportEvery = 1;
    long long checkpointEvery = 0;  // steps between checkpoints (0: only on SIGINT/SIGTERM)
    std::string outDir;             // final.xyz and trajectory.xyz go here
    std::string cache;              // the gradient-map cache (rank 0 reads the map in force from it at the end)
    // A placed bag: end once settled by these settings (Settling.hpp), `steps` the cap.
    std::optional<RunSettings> settle;
};

// Collective: every process calls it with the same scene and start, and the exchanges of its
// kind (core::oneProcess(), parallel::rankExchanges()). Returns the exit code. A signal ends the
// run after the step in progress, with a checkpoint.
int runBatch(const Scene& scene, RunStart start, const BatchOptions& options, core::ExchangeMaker exchanges);

// Set by SIGINT/SIGTERM/SIGUSR1 once installBatchSignals() ran: batch runs stop at the next step.
void installBatchSignals();
bool batchStopRequested();

// A batch run whose step ended unsound: no final.xyz, the last sound state (if the run had one)
// as the checkpoint, the reason said. Returns kExitUnsound (ExitCodes.hpp).
int stopUnsound(const core::UnsoundState& e, const std::optional<core::SoundSnapshot>& last, const core::Model& model,
                const std::string& checkpoint, const std::string& outDir);

}  // namespace bop::app
