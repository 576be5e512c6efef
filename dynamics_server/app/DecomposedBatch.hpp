#pragma once
// bop-server's batch run at more than one rank (mpirun -np N): the scene's particles are split
// over a Cartesian grid of subdomains (parallel/), stepped, and reported from rank 0 with the
// same summary line as a single-process run plus the decomposition's own figures.
#include "SceneConfig.hpp"

#include <string>

namespace bop::app {

struct BatchOptions {
    long long steps = 0, snapshotEvery = 0, reportEvery = 1;
    std::string outDir;  // final.xyz and trajectory.xyz go here (written by rank 0)
};

// Collective: every rank calls it with the same scene and particles. Returns the exit code.
int runDecomposedBatch(const Scene& scene, const core::Particles& particles, long long firstStep,
                       const BatchOptions& options);

}  // namespace bop::app
