#pragma once
// The pair forces of a step: LJ for every pair, co-normal and co-planar for surface particles
// with oriented weights (paper eqs. 2-8), over a Verlet neighbour list built from cell lists with
// a half stencil (each pair once, asymmetric weights applied per side), its pruned copies, and
// the chunks that run the loops (LjPairLoop, OrientedPairLoop) on the threads.
#include "ForceStats.hpp"
#include "MapInForce.hpp"
#include "Model.hpp"
#include "NeighbourList.hpp"
#include "PairChunks.hpp"
#include "PairKernel.hpp"
#include "Particles.hpp"

namespace bop::core {

// Particles owned elsewhere (another rank's subdomain) that the pair terms read: positions
// (already shifted to this side of a periodic face), normals and species. Between two builds
// of the neighbour list the halo holds the same ghosts in the same order.
struct Halo {
    std::vector<Eigen::Vector3d> pos, normal;
    std::vector<std::uint8_t> species;
    std::vector<std::uint64_t> id;  // global ids (for their owners' bookkeeping; not read here)
    std::size_t size() const { return pos.size(); }
};

// What the pair loops read per neighbour-list entry (cell order, ghosts included), gathered from
// the particles and the halo: species when the list is built, normals and curvature weights
// every step; and where they add forces and torques.
struct PairEntries {
    std::vector<std::uint8_t> species;
    std::vector<Eigen::Vector3d> normal;  // unit normals (oriented pairs only)
    std::vector<float> curvature;         // co-planar curvature weights, 1 without a map (oriented only)
    std::vector<Eigen::Vector3d> force;   // energy/length
    std::vector<Eigen::Vector3d> torque;  // energy (oriented only)
};

class PairForces {
public:
    // map: the run has a gradient map (PairKernel).
    PairForces(const Model& model, const Params& params, bool map);

    // Adds the pair forces and torques to particles.force and .torque and fills the pair fields
    // of stats, over the region of `maps`. curvature: per particle, the co-planar weight from the
    // map (MapForces); halo ghosts' are looked up in the map in force. With `energies` false
    // stats.pairEnergy is 0.
    void add(const Model& model, const MapInForce& maps, Particles& particles, const Halo* halo,
             const std::vector<float>& curvature, ForceStats& stats, bool energies, PhaseTimes* times);

    // ForceField::setParams: the kernel's tables again, the list kept unless its pairs change.
    void setParams(const Model& model, const Params& params);
    // ForceField::listHolds and requestRebuild.
    bool listHolds(const Box& region, const Particles& particles);
    void requestRebuild() { revision_ = ~std::uint64_t(0); }

    bool oriented() const { return oriented_; }  // some species pair has oriented weights
    const NeighbourList& neighbours() const { return list_; }
    const PrunedPairs& pruned() const { return pruned_; }
    double pruneSkin() const { return prune_; }  // length units; 0: the loops read the whole list
    std::size_t chunks() const { return chunks_.count(); }
    double listRange() const;  // the largest cutoff + skin, length units
    // The LJ list's least cell width, length units.
    double cellWidth() const { return (kernel_.lj().cutoff() + skin_) / NeighbourList::kCellsPerRange; }
    static double listRange(const Model& model, const Params& params);  // the same of any model and map

    // Reference O(N^2) pair forces (tests): PairKernel::apply pair by pair, the weights of
    // `params`, the curvature weights of the model's whole map, no lists.
    static void bruteForce(const Model& model, const Params& params, Particles& particles, ForceStats& stats);

private:
    void updateList(const Box& region, const Particles& particles, const Halo* halo);
    void gatherEntries(const Model& model, const GradientMap* map, const Particles& particles, const Halo* halo,
                       const std::vector<float>& curvature);

    PairKernel kernel_;           // weights and evaluators of this model
    std::vector<char> isVolume_;  // per species number
    std::vector<char> isWide_;    // per species number: in the oriented (wide) pairs
    bool oriented_ = false;       // some species pair has co-normal or co-planar weights
    bool map_ = false;            // the run has a gradient map
    bool mixed_ = false;          // Integration::mixedPrecision
    double skin_ = 0;             // neighbour-list skin, length units
    double prune_ = 0;            // inner skin of pruned_, length units (0: no pruning)
    NeighbourList list_;
    PrunedPairs pruned_;
    NeighbourList::Wide wide_;  // the members of the last build's wide pairs
    PairChunks chunks_;         // the pair loops on the threads, planned per list build
    std::size_t chunkedBuild_ = 0;
    std::uint64_t revision_ = ~std::uint64_t(0);  // particles.revision at the last build
    std::size_t speciesBuild_ = 0;                // list build that entries_.species was gathered for
    bool heldSinceCompute_ = false;               // listHolds() said yes since the last add()
    PairEntries entries_;
    std::vector<std::uint64_t> keys_;  // the last build's ids, particles then ghosts
};

}  // namespace bop::core
