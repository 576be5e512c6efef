#pragma once
// One rank's share of a decomposed run: the particles of its subdomain, a halo of the
// neighbours' particles within cutoff + skin, and the same integrator and force field as a
// single process (core/), with MPI only here.
//
// Each step: commands queued on rank 0 are broadcast and applied on every rank; O-B-A without wrapping; every rank asks its neighbour list whether it still holds
// (no particle moved more than half the skin); if any says no, all wrap positions into the
// periodic box, migrate particles that left their subdomain (staged x, y, z, so diagonal moves
// need no extra messages) and rebuild the halo; otherwise the halo's positions and normals are
// refreshed along the same send lists. Then forces (pairs with halo ghosts are computed on both
// sides, each side keeping its own particle's force: one message round per step instead of a
// second one returning ghost forces), B-O, and reductions gathered in rank order.
//
// Balance: the cut planes start uniform and move to the particle-count quantiles at start-up and
// whenever a rebuild finds the most loaded rank more than 10% above the mean.
//
// Construction (births and deaths, paper §3.6): every rank checks the map voxels of its own
// subdomain against its particles and a halo widened to the birth front; the candidates and
// death marks are gathered so that every rank makes the same global choice (caps, conflicts)
// as a single process would, and the owner of each position adds the particle
// (DecomposedConstruction.cpp). Ids stay unique by construction (core/ConstructionSteps.hpp).
//
// Gradient map: each rank holds the window of its subdomain plus a margin
// (shape/GradientMapCrop.hpp), taken again from the MapSource when balancing moves it; with
// keyframes, that window of every frame, and the frame in force follows the simulation time as
// in a single process (core/Keyframes.hpp).
//
// Halo: staged along the split axes, x then y then z; each stage also forwards the ghosts that
// earlier stages brought, so edges and corners arrive without extra messages. Axes with one rank
// need no messages: the core makes the periodic images itself.
#include "Comm.hpp"
#include "Commands.hpp"
#include "DecomposedOptions.hpp"
#include "DecomposedRun.hpp"
#include "Decomposition.hpp"
#include "core/ForceField.hpp"
#include "core/Integrator.hpp"

#include <memory>
#include <optional>

namespace bop::parallel {

class DecomposedSimulation {
public:
    // model: the whole scene's model; all: every particle (the same on every rank; each rank
    // keeps those in its subdomain). Computes the first forces.
    DecomposedSimulation(const CartComm& comm, std::shared_ptr<const core::Model> model, const core::Particles& all,
                         DecomposedOptions options = {});

    // core::UnsoundState on every rank when the step ends in an unsound state on any.
    void step();
    // On rank 0: queue a command; every rank applies it at the start of the next step (rank 0
    // broadcasts the queue then). std::logic_error on other ranks.
    void submit(const Command& command);
    void run(long long steps) { for (long long s = 0; s < steps; ++s) step(); }
    // Forces again for the current state, with energies.
    void refreshForces();
    void setEnergyEvery(long long n) { energyEvery_ = n > 0 ? n : 1; }

    const core::Particles& particles() const { return p_; }  // this rank's
    const core::Halo& halo() const { return halo_; }
    const core::Model& subModel() const { return sub_; }  // the model over this subdomain, its map window
    const Decomposition& decomposition() const { return dec_; }
    core::ProbeState& probe() { return probe_; }
    long long stepCount() const { return step_; }  // step number (firstStep + steps done)
    const core::Construction& construction() const { return construction_; }
    std::size_t mapBytes() const;  // this rank's window of the gradient map (of every keyframe)
    std::size_t haloBytesPerStep() const { return haloBytes_; }  // sent by this rank, last update
    std::size_t migrations() const { return migrations_; }       // particles this rank sent away
    std::size_t rebuilds() const { return rebuilds_; }           // halo and list rebuilds
    double exchangeSeconds() const { return exchangeSeconds_; }  // in halo, migration and the rebuild vote
    std::size_t rebalances() const { return rebalances_; }
    double imbalanceNow() const;  // most particles on one rank over the mean (collective)
    double initialImbalance() const { return initialImbalance_; }  // with uniform cuts, before balancing
    Totals totals() const;
    // Voxel counts of every keyframe's whole map (one entry for a static shape; none without a map).
    const std::vector<core::MapVolume>& frameVolumes() const { return frameVolumes_; }
    // Every particle, sorted by id, on every rank (for tests and snapshots).
    core::Particles gather() const;
    core::Particles gather(const core::Particles& mine) const;  // the same of every rank's `mine`
    bool soundEverywhere() const;  // core::sound() of every rank's particles (collective)

private:
    struct Stage {
        int axis = 0;
        std::vector<std::uint32_t> toLower, toUpper;  // sources: particle i, or size() + halo index
        Eigen::Vector3d lowerShift = Eigen::Vector3d::Zero(), upperShift = Eigen::Vector3d::Zero();
        std::size_t fromUpperAt = 0, fromUpperCount = 0, fromLowerAt = 0, fromLowerCount = 0;  // halo ranges
    };
    void wrapAndMigrate();  // one hop along each split axis
    void migrateHome();     // hops until every particle is on the rank that owns its position
    // Cut planes to the particle-count quantiles of every axis, then particles to their new
    // ranks (as many hops as needed) and a new halo. Collective.
    void rebalance();
    void buildHalo(double range);
    void construct(std::vector<core::ConstructionEvent> events);  // DecomposedConstruction.cpp
    Eigen::Vector3d defaultSeed(int species) const;              // collective
    void cropMap();                                              // the windows of sub_.box, if it moved
    void applyKeyframe(double time);                             // Simulation::applyKeyframe's twin
    bool mine(const Eigen::Vector3d& x) const { return dec_.owner(x) == comm_.coords(); }
    void updateHalo();
    void forces(bool energies);
    void apply(const Command& command);
    [[noreturn]] void throwUnsound() const;  // collective: core::UnsoundState naming what a rank found
    static void setWeight(core::Model& m, const Command& c);  // std::invalid_argument if out of range
    Eigen::Vector3d sourcePos(std::uint32_t s) const { return s < p_.size() ? p_.pos[s] : halo_.pos[s - p_.size()]; }

    const CartComm& comm_;
    std::shared_ptr<const core::Model> model_;  // the whole box
    core::ForceField field_;                     // built from the model alone; the box comes per call
    Decomposition dec_;
    core::Model sub_;                            // the same model over this rank's subdomain
    core::Particles p_;
    core::Halo halo_;
    std::vector<Stage> stages_;
    core::DragFactors drag_;
    core::ProbeState probe_;
    core::ForceStats stats_;
    core::PhaseTimes times_;
    double kinetic_ = 0, range_ = 0;
    long long step_ = 0, energyEvery_ = 1;
    std::size_t haloBytes_ = 0, migrations_ = 0, rebuilds_ = 0;
    double exchangeSeconds_ = 0, initialImbalance_ = 1;
    std::size_t rebalances_ = 0;
    std::vector<double> out_[2], in_[2];  // message buffers, kept to avoid fresh pages every step
    std::vector<double> commands_;        // queued on rank 0, encoded
    core::Construction construction_;
    bool forcesStale_ = false;  // a command changed the weights since the last forces
    std::optional<MapSource> mapSource_;
    shape::VoxelWindow window_;
    std::vector<std::shared_ptr<const GradientMap>> subFrames_;  // this window of every keyframe
    std::vector<core::MapVolume> frameVolumes_;                  // whole-map counts per keyframe
    core::KeyframeAt keyframe_;
};

}  // namespace bop::parallel
