#pragma once
// From a loaded scene to a running simulation: the gradient map (built, or read from the cache),
// the box around it, the initial particles (a restart file, a bulk lattice, or none for a bag
// built by its construction timeline) and the probe.
#include "app/scene/SceneConfig.hpp"
#include "core/Simulation.hpp"
#include "shape/ShapeBuilder.hpp"

#include <iosfwd>
#include <memory>
#include <string>

namespace bop::app {

// A run's start (core/Run.hpp), for every mode and process count: every process calls it. Rank 0
// checks the cache and builds the map into it if missing or stale while the others wait
// (waitForAll); the run then reads only the map windows each process needs from the cache file,
// which must therefore lie on a filesystem every process sees. restart: extended XYZ file ("" =
// none); progress: messages while the map is built.
struct RunStart {
    // What the start derives from the scene, which it leaves as parsed: the scene's model with its
    // box around the map, the timeline with a default seed in every piece of its species
    // (PieceSeeds.hpp), the probe with its position in simulation units.
    std::shared_ptr<const core::Model> model;
    std::vector<core::ConstructionEvent> timeline;
    core::ProbeState probe;
    core::Particles particles;
    long long firstStep = 0;
    core::SimulationOptions options;
    // A restart file's settling state (its Settle=, app/runs/Settling.hpp) and the file's name;
    // empty: settle from the start.
    std::string settle, settleFile;
};
RunStart startRun(const Scene& scene, const std::string& cache, const std::string& restart, bool root,
                  const std::function<void()>& waitForAll, const shape::ProgressFn& progress = {});

// For a batch run that ends once settled (a placed bag's build): the start's model steps at the
// scene's settleTimeStep instead of its time_step. A served run, or one that goes on past
// settling, keeps time_step.
void useSettleTimeStep(const Scene& scene, RunStart& start);

// The particles to start from (a restart file's, a bulk lattice, or none) and the construction:
// `timeline`, with a checkpoint's birth switches and seed count when the restart file is one
// (app/Checkpoint.hpp). model: the start's; firstStep: the file's step, else 0; settle: the file's
// Settle=; cuts, yields: the file's Cuts= and Yields=.
core::Particles initialParticles(const Scene& scene, const core::Model& model,
                                 const std::vector<core::ConstructionEvent>& timeline, const std::string& restart,
                                 long long& firstStep, core::Construction& construction, std::string& settle,
                                 std::vector<core::CutCommand>& cuts, std::vector<std::vector<std::uint64_t>>& yields);

// "placed on the map: ..." with each species' count against its ideal at r0 spacing.
std::string placementReport(const core::Model& model, const std::vector<app::PlacedSpecies>& placed);

// Species names by number (index 0 unused), as snapshots write them.
std::vector<std::string> speciesNames(const core::Model& model);

}  // namespace bop::app
