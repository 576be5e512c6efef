#pragma once
// One process's simulation: the model (read-only during a step), the particles, the probe and
// the construction timeline, advanced by step(). Free of MPI, sockets and files.
#include "BloodPressure.hpp"
#include "Construction.hpp"
#include "ForceField.hpp"
#include "Integrator.hpp"

#include <memory>

namespace bop::core {

struct StepStats {
    long long step = 0;          // steps completed
    double time = 0;             // simulation time
    double kinetic = 0;          // kinetic energy (translation + rotation)
    ForceStats forces;           // energies, virial and probe reaction of the last force evaluation
    ConstructionCounts built;    // births and deaths at the start of the last step
    BloodSums blood;             // kinetic sum and count of the volume particles after the step
    KeyframeAt keyframe;         // the gradient-map frame(s) of the last force evaluation
    double bloodVolume = 0;      // volume voxels of the map(s) in force, length^3 (eq. 15's V)
    double cavityVolume = 0;     // every voxel of the bags in the map(s) in force, length^3
    double total() const { return kinetic + forces.pairEnergy + forces.probeEnergy; }
};

struct StepTimes {
    PhaseTimes forces;           // neighbour list, pairs, gradient map, probe
    double integrate = 0;        // kicks and drift, s
    double construction = 0;     // births and deaths, s
    double total() const { return forces.neighbours + forces.pairs + forces.gradientMap + forces.probe + integrate + construction; }
};

class Simulation {
public:
    Simulation(std::shared_ptr<const Model> model, Particles particles, Construction construction,
               long long firstStep = 0);

    // core::UnsoundState (SoundState.hpp) when the step ends in a state not fit to go on from.
    void step();
    void run(long long steps) { for (long long s = 0; s < steps; ++s) step(); }

    const Model& model() const { return *model_; }
    void setModel(std::shared_ptr<const Model> m);  // between steps
    const Particles& particles() const { return p_; }
    Particles& particles() { return p_; }  // between steps (commands, tests)
    ProbeState& probe() { return probe_; }
    Construction& construction() { return construction_; }
    const Construction& construction() const { return construction_; }
    const StepStats& stats() const { return stats_; }
    const StepTimes& times() const { return times_; }
    void resetTimes() { times_ = StepTimes{}; }
    void setTimes(const StepTimes& t) { times_ = t; }  // carried over when a run continues from a checkpoint
    const ForceField& forceField() const { return forces_; }

    // Voxel counts of each keyframe's map (one entry for a static shape, none without a map).
    const std::vector<MapVolume>& frameVolumes() const { return frameVolumes_; }

    // Recomputes forces for the current state (after commands changed particles or the model).
    void refreshForces();

    // Compute the LJ pair energy only every n steps (1 = every step, the default); the stats of
    // other steps leave it out. Batch runs set their report period here.
    void setEnergyEvery(long long n) { energyEvery_ = n > 0 ? n : 1; }

private:
    // The map(s) in force at `time`: the model's map follows the keyframes (construction reads
    // it), the force field blends towards the next frame.
    void applyKeyframe(double time);

    std::shared_ptr<const Model> model_;
    std::vector<MapVolume> frameVolumes_;
    Particles p_;
    Construction construction_;
    ProbeState probe_;
    DragFactors drag_;
    ForceField forces_;
    StepStats stats_;
    StepTimes times_;
    bool forcesValid_ = false;
    long long energyEvery_ = 1;
};

}  // namespace bop::core
