#pragma once
// Building a bag by birth and death (paper §3.6, docs/physics.md §7): the user seeds one particle
// per species; where a species' voxels lack particles next to existing ones, particles are born;
// where two particles are too close, one dies. Rate-limited, surfaces first, then volumes. This
// class holds the timeline, the switches and the counts; a step (Simulation.cpp construct())
// does the checks with the pieces of ConstructionSteps.hpp, every ten steps while a birth is on:
// deaths, then births of every species whose birth is on (only those species lose particles).
// Deterministic for a given seed: every choice is ordered by a counter-based hash of
// (seed, step, species, voxel or id), never by iteration order.
#include "Model.hpp"
#include "Particles.hpp"

#include <algorithm>
#include <optional>
#include <vector>

namespace bop::core {

struct ConstructionParams {
    int everySteps = 10;        // steps between birth/death checks
    double deathR0 = 0.5;       // a pair closer than this dies (one of the two), multiples of r0
    double sameR0 = 0.8;        // no birth within this of a particle of the same species, r0
    double anyR0 = 0.69;        // no birth within this of any particle, r0
    double frontR0 = 2.0;       // births only within this of a particle of the same species, r0
    double capFraction = 0.05;  // at most max(1, ceil(fraction * N_species)) births (deaths) per check
    std::uint64_t seed = 1;     // random seed of every construction choice
};

struct ConstructionEvent {
    enum class Action { Seed, BirthOn, BirthOff };
    long long step = 0;  // applied at the start of this step
    Action action = Action::Seed;
    int species = 1;
    std::optional<Eigen::Vector3d>
        positionVoxels;  // seed position in voxel coordinates; default: a voxel of the species
};

struct ConstructionCounts {
    std::size_t births = 0, deaths = 0;
};

class Construction {
public:
    Construction(ConstructionParams params, std::vector<ConstructionEvent> timeline, int speciesCount);

    // Commands (scripted by the timeline, or sent by a viewer between steps). seed() adds the
    // particle and returns its id; every process of a decomposed run calls it (in the same
    // order), and only the one that owns the position passes add = true.
    std::uint64_t seed(const Model& model, const GradientMap* map, Particles& p, int species,
                       const Eigen::Vector3d& position, bool add = true);
    // In `map` (the whole map), simulation units.
    Eigen::Vector3d defaultSeedPosition(const Model& model, const GradientMap* map, int species) const;
    void setBirth(int species, bool on);
    bool birthOn(int species) const { return birth_[std::size_t(species)]; }
    const std::vector<char>& birthSwitches() const { return birth_; }  // per species number (index 0 unused)
    std::uint64_t seedCount() const { return seeds_; }                 // seeds placed so far
    // Ids (docs/dynamics.md "Construction"): every new particle, seed or birth, takes the next
    // free id, counting on from the largest id of the particles the run starts with. Every
    // process of a decomposed run counts every seed and every birth in the same order, so all
    // agree without a message, and ids stay small (below 2^31 for the first two billion
    // particles: readers of 32-bit integer columns take them).
    std::uint64_t nextId() const { return nextId_; }
    void reserveIds(std::uint64_t largestInUse) { nextId_ = std::max(nextId_, largestInUse + 1); }
    std::uint64_t takeIds(std::uint64_t n) {  // the first of n consecutive ids
        const std::uint64_t first = nextId_;
        nextId_ += n;
        return first;
    }
    // A restart from a checkpoint: its birth switches (per species number from 1), seed count and
    // next id (0: not recorded; the run counts on from its particles' largest id). A snapshot
    // without them restarts with every birth off. std::invalid_argument for a count of switches
    // other than the species count.
    void restore(const std::vector<char>& births, std::uint64_t seeds, std::uint64_t nextId = 0);
    bool building() const;                                          // some species' birth is on
    bool checkDue(long long step) const;                            // a birth/death check runs at this step
    std::vector<ConstructionEvent> eventsAt(long long step) const;  // the timeline's, in order
    int speciesCount() const { return int(birth_.size()) - 1; }

    const ConstructionParams& params() const { return params_; }
    ConstructionCounts totals() const { return totals_; }
    void addToTotals(const ConstructionCounts& c) {
        totals_.births += c.births;
        totals_.deaths += c.deaths;
    }

private:
    ConstructionParams params_;
    std::vector<ConstructionEvent> timeline_;
    std::vector<char> birth_;
    ConstructionCounts totals_;
    std::uint64_t seeds_ = 0;   // seeds so far
    std::uint64_t nextId_ = 1;  // the id the next new particle takes
};

// SplitMix64 of a combination of integers: the construction's only source of randomness.
std::uint64_t mixHash(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0, std::uint64_t d = 0);

}  // namespace bop::core
