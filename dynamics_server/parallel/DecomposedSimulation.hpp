#pragma once
// One rank's share of a decomposed run: the one step of every run (core/Simulation.hpp) with
// this rank's exchange (MpiExchange.hpp: its subdomain, migration, the halo plan, balancing and
// reductions). Collective: every rank makes every call.
#include "Comm.hpp"
#include "Commands.hpp"
#include "DecomposedOptions.hpp"
#include "MpiExchange.hpp"
#include "core/Simulation.hpp"

namespace bop::parallel {

using Totals = core::Totals;

class DecomposedSimulation {
public:
    // model: the whole scene's model; all: every particle (the same on every rank; each rank
    // keeps those in its subdomain). Computes the first forces.
    DecomposedSimulation(const CartComm& comm, std::shared_ptr<const core::Model> model, const core::Particles& all,
                         DecomposedOptions options = {});

    void step() { sim_.step(); }
    // On rank 0: queue a command; every rank applies it at the start of the next step.
    // std::logic_error on other ranks, std::invalid_argument when refused.
    void submit(const Command& command) { sim_.submit(command); }
    bool commandsQueued() const { return sim_.commandsQueued(); }
    void run(long long steps) { sim_.run(steps); }
    void refreshForces() { sim_.refreshForces(); }
    void setEnergyEvery(long long n) { sim_.setEnergyEvery(n); }
    void energiesNextStep() { sim_.energiesNextStep(); }
    bool energiesCurrent() const { return sim_.energiesCurrent(); }

    const core::Particles& particles() const { return sim_.particles(); }  // this rank's
    const core::Halo& halo() const { return sim_.halo(); }
    const core::Model& subModel() const { return sim_.model(); }  // the model over this subdomain, its map window
    const Decomposition& decomposition() const { return exchange_.decomposition(); }
    core::ProbeState& probe() { return sim_.probe(); }
    long long stepCount() const { return sim_.stepCount(); }  // step number (firstStep + steps done)
    const core::Construction& construction() const { return sim_.construction(); }
    std::size_t mapBytes() const { return sim_.mapBytes(); }  // this rank's window of the gradient map (every keyframe)
    std::size_t haloBytesPerStep() const { return exchange_.haloBytesPerStep(); }  // sent by this rank, last update
    std::size_t migrations() const { return exchange_.migrations(); }              // particles this rank sent away
    std::size_t rebuilds() const { return sim_.rebuilds(); }                       // halo and list rebuilds
    double exchangeSeconds() const { return sim_.exchangeSeconds(); }  // in halo, migration and the rebuild vote
    std::size_t rebalances() const { return exchange_.rebalances(); }
    double imbalanceNow() {
        return exchange_.imbalance(sim_.particles().size());
    }  // most particles on one rank over the mean
    double initialImbalance() const { return exchange_.initialImbalance(); }  // with uniform cuts, before balancing
    Totals totals() const { return sim_.totals(); }
    // Voxel counts of every keyframe's whole map (one entry for a static shape; none without a map).
    const std::vector<core::MapVolume>& frameVolumes() const { return sim_.frameVolumes(); }
    // Every particle, sorted by id, on every rank (for tests and snapshots).
    core::Particles gather() const { return sim_.gather(); }
    core::Particles gather(const core::Particles& mine) const {
        return sim_.gather(mine);
    }  // the same of every rank's `mine`
    bool soundEverywhere() const { return sim_.soundEverywhere(); }

private:
    MpiExchange exchange_;
    core::Simulation sim_;
};

}  // namespace bop::parallel
