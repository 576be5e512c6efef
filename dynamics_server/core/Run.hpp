#pragma once
// A run, the same at one process and at N: the one step (Simulation.hpp) over this process's
// exchange, and what the drivers (app/runs/: the batch loop and the served loop) need around it:
// the start (every particle of the scene, each process keeping those it owns; the gradient map
// in windows), the last sound state, going on from a checkpoint (reseat), the counters, a frame
// gathered on rank 0 and rank 0's decisions. Every call is collective unless it says otherwise.
// Free of MPI, sockets and files: the exchange brings the other processes, if any
// (parallel/RankExchanges.hpp makes MPI ranks' exchanges).
#include "Simulation.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

namespace bop::core {

// A state frame's arrays, gathered to rank 0 in rank order (each process's particles in its own
// order: the same order at a fixed process count). Empty on other ranks.
struct FrameArrays {
    std::vector<float> positions, normals;  // 3 per particle, length / unit
    std::vector<std::uint8_t> species;
    std::vector<std::uint64_t> ids;
};

struct RunCounters {                // summed over processes, identical on every process
    double haloBytesPerStep = 0;    // bytes the processes sent for the halo in the last step
    double migrations = 0;          // particles that changed process so far
    double rebuilds = 0;            // halo and neighbour-list rebuilds so far (per process)
    double imbalance = 1;           // most particles on one process over the mean
    double exchangeSecondsMax = 0;  // the most time one process spent exchanging (halo, migration, votes)
    double initialImbalance = 1;    // imbalance with uniform cuts, before the first balancing
    double rebalances = 0;          // times the cut planes moved (start-up included)
    double mapBytesMax = 0;         // the largest window of the gradient map one process holds, bytes
    double births = 0, deaths = 0;  // construction so far
};

// This process's exchange for a box and the widest halo the run needs (haloReach), made at the
// start and again at each reseat.
using ExchangeMaker = std::function<std::unique_ptr<Exchange>(const Box& whole, double reach)>;
ExchangeMaker oneProcess();  // the base Exchange: nothing to exchange

// Surface and volume particles, and those in the voxels of their own species (0 without a map),
// over every process (reports: not in totals(), which a served run asks every pass; the final
// fidelity is app::measureFidelity's on the whole map).
struct ShapeCounts {
    double surface = 0, surfaceInOwn = 0, volume = 0, volumeInOwn = 0;
};

class Run {
public:
    // `all`: every particle of the scene, the same on every process.
    Run(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options = {},
        ExchangeMaker exchanges = oneProcess());
    ~Run();

    // UnsoundState (SoundState.hpp) on every process when the step ends in an unsound state:
    // lastSound() then holds the state to save.
    void step();
    void run(long long steps) {
        for (long long s = 0; s < steps; ++s) step();
    }
    void refreshForces();
    void resetTimes();  // this process's step times from zero (after the set-up's forces)
    void setEnergyEvery(long long n);
    void energiesNextStep();                 // the next step computes energies too
    bool energiesCurrent() const;            // the last forces came with energies (the same everywhere)
    void setProbe(const ProbeState& probe);  // the same on every process
    // The minimiser steps from here on (Simulation::minimise: afresh, or from the state `from`; a
    // reseat carries its state); none: the damped dynamics again, from rest.
    void minimise(std::optional<FireParams> fire, const std::optional<FireState>& from = std::nullopt);
    bool minimising() const;
    std::optional<FireState> minimiserState() const;  // the same on every process
    // On rank 0 only: a command every process applies at the start of the next step
    // (std::invalid_argument if it is refused, std::logic_error on other ranks).
    void submit(const Command& command);
    bool commandsQueued() const;        // on rank 0: submitted, not yet applied by a step
    const Params& paramsAhead() const;  // on rank 0: the params once the queued commands apply
    // What rank 0 decided for this pass of a run loop, on every process (one small broadcast).
    struct Decision {
        int stop = 0;  // 0: go on; otherwise why the loop stops (the loop's own codes)
        bool step = false, publish = false, feedback = false;
    };
    Decision agree(const Decision& mine);
    long long stepNumber() const;  // steps so far, counted from the scene's first step
    Totals totals() const;
    ShapeCounts shapeCounts() const;                     // over every process, against the map windows in force
    const std::vector<MapVolume>& frameVolumes() const;  // of every keyframe's whole map
    RunCounters counters() const;
    Particles gather() const;  // every particle sorted by id, on every process
    // The last sound state (the start's, and again every kSoundSnapshotEvery steps), gathered:
    // every particle by id, the construction and the step. Nothing when the run never was sound
    // (its start was not).
    std::optional<SoundSnapshot> lastSound() const;
    const Construction& construction() const;
    // Goes on from `all` (every particle as a checkpoint holds them, the same on every process)
    // at `step` with `construction`: a fresh start, as a restart from that file makes, with this
    // run's probe, energy period, map and step times.
    void reseat(const Particles& all, const Construction& construction, long long step);
    // What a state frame carries, on rank 0 (lighter than gather()), into `into`, whose arrays
    // keep their capacity (a frame's memory reused for the next one).
    void gatherFrame(FrameArrays& into) const;
    int rank() const;
    int size() const;
    std::array<int, 3> grid() const;  // processes along each axis
    // This process's share: the step over its region (its particles, halo, model window) and its
    // exchange, for tests and reports.
    const Simulation& simulation() const;
    Simulation& simulation();  // between steps (tests: particles added, switches turned)
    const Exchange& exchange() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace bop::core
