#pragma once
// All forces and torques of one step (paper eqs. 2-11 without the drag, which the integrator
// applies exactly): the gradient map's (MapForces), the pairs' (PairForces: LJ, co-normal and
// co-planar over the neighbour list) and the probe's (eq. 9's particle or a sphere), in that order.
#include "MapForces.hpp"
#include "PairForces.hpp"

namespace bop::core {

// The probe as a rigid sphere at `centre` (docs/physics.md §2.5): adds to each particle's force,
// and to stats' probe reaction (minus their sum) and probe energy.
void sphereProbeForces(const ProbeSphere& sphere, const Eigen::Vector3d& centre, Particles& particles,
                       ForceStats& stats);

class ForceField {
public:
    // map: the run has a gradient map (its curvature weights weight the co-planar terms).
    ForceField(const Model& model, const Params& params, bool map);

    // Overwrites particles.force and particles.torque, over the region and with the map of
    // `maps`. energies = false skips the pair energies (stats.pairEnergy is then 0); the forces do
    // not depend on it. halo: ghosts owned elsewhere; pairs with them count for the particles
    // here, their energy and virial by half.
    void compute(const Model& model, const MapInForce& maps, const ProbeState& probe, Particles& particles,
                 ForceStats& stats, PhaseTimes* times = nullptr, bool energies = true, const Halo* halo = nullptr);

    // Weights of a command between steps: the kernel's tables again, the neighbour list kept
    // unless the pairs it must hold change (the oriented pairs' members, a cutoff).
    void setParams(const Model& model, const Params& params) { pairs_.setParams(model, params); }

    // Whether the neighbour list still serves these particles (none added or removed, none moved
    // more than half the skin). A decomposed run asks every rank and rebuilds on all if one says
    // no: requestRebuild() makes the next compute() build the list (with the new halo).
    // The next compute() trusts a "yes" (positions unchanged in between) and measures no again.
    bool listHolds(const Box& region, const Particles& particles) { return pairs_.listHolds(region, particles); }
    void requestRebuild() { pairs_.requestRebuild(); }

    const PairForces& pairs() const { return pairs_; }  // the neighbour list, its pruned copies, chunks

private:
    void probeForces(const Model& model, const ProbeState& probe, Particles& particles, ForceStats& stats);

    MapForces map_;
    PairForces pairs_;
};

}  // namespace bop::core
