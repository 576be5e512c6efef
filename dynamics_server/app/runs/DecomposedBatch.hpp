#pragma once
// bop-server's batch run at more than one rank (mpirun -np N): the scene's particles are split
// over a Cartesian grid of subdomains (parallel/), stepped, and reported from rank 0 with the
// same summary line as a single-process run plus the decomposition's own figures.
#include "app/cardiac/CardiacRun.hpp"
#include "app/scene/SceneConfig.hpp"
#include "app/scene/SimulationSetup.hpp"
#include "parallel/DecomposedRun.hpp"

#include <string>

namespace bop::app {

struct BatchOptions {
    long long steps = 0, snapshotEvery = 0, reportEvery = 1;
    long long checkpointEvery = 0;  // steps between checkpoints (0: only on SIGINT/SIGTERM)
    std::string outDir;             // final.xyz and trajectory.xyz go here (written by rank 0)
    std::string cache;  // the gradient-map cache (rank 0 reads it whole at the end for the fidelity figures)
};

// Collective: every rank calls it with the same scene and start. Returns the exit code.
int runDecomposedBatch(const Scene& scene, DecomposedStart start, const BatchOptions& options);

// The ventricle's measurements after a step of a decomposed run (collective: the reductions
// every step, the particles gathered every volume_every_steps; the series is kept on rank 0).
void recordCardiac(CardiacRun& cardiac, parallel::DecomposedRun& run, const core::Model& model);

}  // namespace bop::app
