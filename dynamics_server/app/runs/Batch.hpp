#pragma once
// bop-server's batch run (--no-listen), at one process or N ranks alike: the run's lifecycle
// (RunLifecycle.hpp: start, stop flag, checkpoints, unsound states, final files) with a pass of
// one step and its progress reports, snapshots and settling checks, then the Table-1 style
// summary (BatchReport.hpp). Rank 0 writes the files.
#include "app/scene/RunStart.hpp"
#include "core/Run.hpp"

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

}  // namespace bop::app
