#pragma once
// A decomposed run over MPI_COMM_WORLD for tools outside parallel/ (no <mpi.h> here): every rank
// constructs it with the whole scene's model and particles, steps it, and reads reductions
// that are the same on every rank. Collective: every call must be made on every rank.
#include "Commands.hpp"
#include "DecomposedOptions.hpp"
#include "Decomposition.hpp"
#include "core/Simulation.hpp"

#include <Eigen/Core>

#include <array>
#include <memory>
#include <optional>

namespace bop::parallel {

class MpiExchange;            // MpiExchange.hpp (with <mpi.h>)
using Totals = core::Totals;  // over all ranks, identical on every rank

// A state frame's arrays, gathered to rank 0 in rank order (each rank's particles in its own
// order: the same order at a fixed rank count). Empty on other ranks.
struct FrameArrays {
    std::vector<float> positions, normals;  // 3 per particle, length / unit
    std::vector<std::uint8_t> species;
    std::vector<std::uint64_t> ids;
};

struct RunCounters {                // summed over ranks, identical on every rank
    double haloBytesPerStep = 0;    // bytes the ranks sent for the halo in the last step
    double migrations = 0;          // particles that changed rank so far
    double rebuilds = 0;            // halo and neighbour-list rebuilds so far (per rank)
    double imbalance = 1;           // most particles on one rank over the mean
    double exchangeSecondsMax = 0;  // the most time one rank spent exchanging (halo, migration, votes)
    double initialImbalance = 1;    // imbalance with uniform cuts, before the first balancing
    double rebalances = 0;          // times the cut planes moved (start-up included)
    double mapBytesMax = 0;         // the largest window of the gradient map one rank holds, bytes
    double births = 0, deaths = 0;  // construction so far
};

class DecomposedRun {
public:
    DecomposedRun(std::shared_ptr<const core::Model> model, const core::Particles& all, DecomposedOptions options = {});
    ~DecomposedRun();

    // core::UnsoundState (core/SoundState.hpp) on every rank when the step ends in an unsound
    // state: lastSound() then holds the state to save.
    void step();
    void run(long long steps) {
        for (long long s = 0; s < steps; ++s) step();
    }
    void refreshForces();
    void setEnergyEvery(long long n);
    void energiesNextStep();                       // core::Simulation's: the next step computes energies too
    bool energiesCurrent() const;                  // the last forces came with energies (the same on every rank)
    void setProbe(const core::ProbeState& probe);  // the same on every rank
    // On rank 0 only: a command every rank applies at the start of the next step
    // (std::invalid_argument if it is refused, std::logic_error on other ranks).
    void submit(const Command& command);
    bool commandsQueued() const;  // on rank 0: submitted, not yet applied by a step
    // What rank 0 decided for this pass of a run loop, on every rank (one small broadcast).
    struct Decision {
        int stop = 0;  // 0: go on; otherwise why the loop stops (the loop's own codes)
        bool step = false, publish = false, feedback = false;
    };
    Decision agree(const Decision& mine);
    long long stepNumber() const;  // steps so far, counted from the scene's first step
    Totals totals() const;
    const std::vector<core::MapVolume>& frameVolumes() const;  // of every keyframe's whole map
    RunCounters counters() const;
    core::Particles gather() const;  // every particle sorted by id
    // The last sound state (the start's, and again every core::kSoundSnapshotEvery steps),
    // gathered: every particle by id, the construction and the step. Collective. Nothing when
    // the run never was sound (its start was not).
    std::optional<core::SoundSnapshot> lastSound() const;
    const core::Construction& construction() const;
    // Goes on from `all` (every particle, as read from a checkpoint, the same on every rank) at
    // `step` with `construction`: a fresh decomposition, as a restart from that file makes, with
    // this run's probe, energy period and map. Collective.
    void reseat(const core::Particles& all, const core::Construction& construction, long long step);
    // What a state frame carries, on rank 0 (lighter than gather()), into `into`, whose arrays
    // keep their capacity (a frame's memory reused for the next one).
    void gatherFrame(FrameArrays& into) const;
    int rank() const;
    int size() const;
    Coords dims() const;
    // This rank's share: the step over its subdomain (its particles, halo, model window) and its
    // exchange (decomposition, migrations, halo bytes), for tests and reports.
    const core::Simulation& simulation() const;
    const MpiExchange& exchange() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace bop::parallel
