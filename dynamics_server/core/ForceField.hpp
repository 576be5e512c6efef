#pragma once
// All forces and torques of one step (paper eqs. 2-11 without the drag, which the integrator
// applies exactly): LJ, co-normal and co-planar pairs over a Verlet neighbour list built from
// cell lists with a half stencil (each pair once, asymmetric weights applied per side),
// gradient-map forces and torques, and the probe particle.
#include "Model.hpp"
#include "NeighbourList.hpp"
#include "PairChunks.hpp"
#include "PairKernel.hpp"
#include "Particles.hpp"

#include <memory>

namespace bop::core {

struct ProbeState {
    bool active = false;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // simulation length units
    ProbeParams params;                                  // k0, k1 (eq. 9)
};

// Particles owned elsewhere (another rank's subdomain) that the pair terms read: positions
// (already shifted to this side of a periodic face), normals and species. Between two builds
// of the neighbour list the halo holds the same ghosts in the same order.
struct Halo {
    std::vector<Eigen::Vector3d> pos, normal;
    std::vector<std::uint8_t> species;
    std::vector<std::uint64_t> id;  // global ids (for their owners' bookkeeping; not read here)
    std::size_t size() const { return pos.size(); }
};

struct ForceStats {
    double pairEnergy = 0;    // LJ + co-normal + co-planar energy (weights symmetrised), energy units
    double probeEnergy = 0;   // energy of the probe's interaction with the particles
    double virial = 0;        // sum over pairs of r_ij . F_j (conservative pair forces), energy
    double virialVolume = 0;  // the same over pairs of two volume particles only
    // sum over volume particles of (x - map centre) . F^GM: the gradient map's wall virial on
    // the blood, -3PV for a gas the map alone contains (energy)
    double wallVirial = 0;
    Eigen::Vector3d probeReaction = Eigen::Vector3d::Zero();  // force of the particles on the probe
    std::size_t pairsInRange = 0;                             // pairs within the LJ cutoff
    std::size_t orientedPairsInRange = 0;                     // pairs with oriented weights within their cutoff
};

struct PhaseTimes {
    double neighbours = 0, pairs = 0, gradientMap = 0, probe = 0;  // seconds, accumulated
    // The two pair loops' time summed over threads (CPU seconds) and the pairs in range they
    // handled, accumulated: ns per pair of each kind.
    double ljLoopSeconds = 0, orientedLoopSeconds = 0;
    double ljPairs = 0, orientedPairs = 0;
};

class ForceField {
public:
    explicit ForceField(const Model& model);

    // Overwrites particles.force and particles.torque. energies = false skips the pair
    // energies (stats.pairEnergy is then 0); the forces do not depend on it. halo: ghosts owned
    // elsewhere; pairs with them count for the particles here, their energy and virial by half.
    void compute(const Model& model, const ProbeState& probe, Particles& particles, ForceStats& stats,
                 PhaseTimes* times = nullptr, bool energies = true, const Halo* halo = nullptr);

    // Weights and potentials' parameters of another model of the same scene (a command between
    // steps): the kernel's tables again, the neighbour list kept unless the pairs it must hold
    // change (the oriented pairs' members, a cutoff).
    void setParams(const Model& model);

    // Whether the neighbour list still serves these particles (none added or removed, none moved
    // more than half the skin). A decomposed run asks every rank and rebuilds on all if one says
    // no: requestRebuild() makes the next compute() build the list (with the new halo).
    // The next compute() trusts a "yes" (positions unchanged in between) and measures no again.
    bool listHolds(const Model& model, const Particles& particles);
    void requestRebuild() { revision_ = ~std::uint64_t(0); }

    // Keyframe blending: until set again, the gradient-map forces are (1 - w) of the model's map
    // plus w of `next` (a map on the same grid; null or w = 0: the model's map alone).
    void setMapBlend(const GradientMap* next, double w) {
        if (next != blendFieldMap_) blendField_.reset(), blendFieldMap_ = nullptr;  // never a field of a freed map
        blendMap_ = w > 0 ? next : nullptr, blendW_ = w;
    }

    // Reference O(N^2) pair forces (for tests): same weights (the map's curvature weights too),
    // no cell lists, PairKernel::apply pair by pair.
    static void computePairsBruteForce(const Model& model, Particles& particles, ForceStats& stats);

    // The co-planar curvature weight at x (1 without a map or for volume species).
    static float curvatureWeight(const Model& model, const Eigen::Vector3d& x, int species);
    const NeighbourList& neighbours() const { return list_; }
    // The pair loops' pruned copies of the list, and their inner skin (length units; 0: the
    // loops read the whole list).
    const PrunedPairs& pruned() const { return pruned_; }
    double pruneSkin() const { return prune_; }
    std::size_t pairChunks() const { return chunks_.count(); }  // the pair loops' pieces of work
    // The largest cutoff + skin (length units): the halo's depth. The LJ pairs are listed to the
    // LJ cutoff + skin, the oriented ones (surface particles with weights) to theirs.
    double listRange() const;
    static double listRange(const Model& model);  // the same of any model, without a force field

private:
    void pairForces(Particles& particles, const Halo* halo, ForceStats& stats, bool energies, PhaseTimes* times);
    void gatherEntries(const Model& model, const Particles& particles, const Halo* halo);
    void gradientMapForces(const Model& model, Particles& particles, ForceStats& stats);
    void probeForces(const Model& model, const ProbeState& probe, Particles& particles, ForceStats& stats);

    PairKernel kernel_;           // weights and evaluators of this model, built once
    std::vector<char> isVolume_;  // per species number
    std::vector<char> isWide_;    // per species number: in the oriented (wide) pairs
    bool oriented_ = false;       // some species pair has co-normal or co-planar weights
    double skin_ = 0;             // neighbour-list skin, length units
    double prune_ = 0;            // inner skin of pruned_, length units (0: no pruning)
    NeighbourList list_;
    PrunedPairs pruned_;
    NeighbourList::Wide wide_;  // the members of the last build's wide pairs
    PairChunks chunks_;         // the pair loops on the threads, planned per list build
    std::size_t chunkedBuild_ = 0;
    std::uint64_t revision_ = ~std::uint64_t(0);  // particles.revision at the last build
    std::size_t speciesBuild_ = 0;                // list build that ss_ was gathered for
    bool heldSinceCompute_ = false;               // listHolds() said yes since the last compute()
    std::unique_ptr<core::GmField> field_;
    std::shared_ptr<const GradientMap> fieldMap_;  // field_'s map, held: a new map never takes its address
    std::unique_ptr<core::GmField> blendField_;    // of blendMap_
    const GradientMap* blendFieldMap_ = nullptr;
    const GradientMap* blendMap_ = nullptr;
    double blendW_ = 0;
    // Per neighbour-list entry (cell order, ghosts included): copies for the pair loop.
    std::vector<Eigen::Vector3d> sp_, sn_, sf_, st_;
    std::vector<std::uint8_t> ss_;
    std::vector<float> sw_;
    std::vector<float> cpWeight_;  // per particle, from the map (1 without a map)
};

}  // namespace bop::core
