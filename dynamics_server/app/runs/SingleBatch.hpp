#pragma once
// bop-server's batch run in one process (--no-listen at one rank): the core Simulation stepped with progress reports,
// snapshots, checkpoints (every `checkpointEvery` steps and on SIGINT/SIGTERM, app/Checkpoint.hpp), the ventricle's
// pressure series when the scene asks for it, and the Table-1 style summary.
#include "app/runs/DecomposedBatch.hpp"
#include "core/SoundState.hpp"
#include "shape/ShapeBuilder.hpp"

#include <optional>
#include <string>

namespace bop::app {

// Returns the exit code. A signal ends the run after the step in progress, with a checkpoint.
int runSingleBatch(Scene& scene, const std::string& restart, const BatchOptions& options,
                   const shape::ProgressFn& progress);

// Set by SIGINT/SIGTERM once installBatchSignals() ran: batch runs stop at the next step.
void installBatchSignals();
bool batchStopRequested();

// A batch run whose step ended unsound: no final.xyz, the last sound state (if the run had one)
// as the checkpoint, the reason said. Returns kExitUnsound (ExitCodes.hpp).
int stopUnsound(const core::UnsoundState& e, const std::optional<core::SoundSnapshot>& last, const core::Model& model,
                const std::string& checkpoint, const std::string& outDir);

}  // namespace bop::app
