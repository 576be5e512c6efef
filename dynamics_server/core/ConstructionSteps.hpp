#pragma once
// The pieces of a construction check (paper §3.6, docs/physics.md §7), split so that a decomposed run
// can do each piece on its own ranks and choose globally in between: a single process calls
// them on all its particles, a rank calls them on its own particles plus the copies of its
// neighbours' (its halo) and gathers what they return. Every choice is ordered by hashes of
// (seed, step, species, voxel or id), so both give the same births and deaths.
#include "Construction.hpp"

#include <functional>

namespace bop::core {

// What one check sees: seen.pos/species/id of particles [0, owned) are the caller's own, the
// rest copies of particles others own. `box` bounds the caller's region (periodic axes wrap);
// `map`: the map in force over it (births need one).
struct ConstructionView {
    const Model& model;
    const Box& box;
    const Particles& seen;
    std::size_t owned;
    const GradientMap* map;
};

struct DeathMark {
    std::uint64_t key = 0;  // hash order in which the cap takes them
    std::uint64_t id = 0;   // the particle that would die
    int species = 0;
};
// Own particles that have a partner closer than deathR0 and lose to it.
std::vector<DeathMark> markDeaths(const ConstructionParams& params, const ConstructionView& view, long long step);
// The ids that die (sorted): marks of the whole model in key order, at most the cap of each
// species; count[s] is the number of particles of species s in the whole model. Only species
// whose birth is on (birthOn[s]) die: one switched off keeps its particles (a ventricle's blood
// is compressed, not thinned).
std::vector<std::uint64_t> chooseDeaths(const ConstructionParams& params, std::vector<DeathMark> marks,
                                        const std::vector<std::size_t>& count, const std::vector<char>& birthOn);

struct BirthCandidate {
    Eigen::Vector3d pos = Eigen::Vector3d::Zero();  // simulation length units
    std::uint64_t key = 0;                          // priority: the smaller key wins
    std::uint64_t voxel = 0;                        // whole-map voxel index
};
// Unblocked front voxels of `species` in the map whose candidate position `mine` accepts.
std::vector<BirthCandidate> birthCandidates(const ConstructionParams& params, const ConstructionView& view, int species,
                                            long long step, const std::function<bool(const Eigen::Vector3d&)>& mine);
// Winners among the candidates of the whole model (any order): no conflicting candidate
// (closer than sameR0) has a smaller key; at most the cap for `have` particles of the species;
// in key order. `box`: the whole model's box.
std::vector<BirthCandidate> chooseBirths(const ConstructionParams& params, const Box& box,
                                         std::vector<BirthCandidate> candidates, std::size_t have);
// Adds a born particle with id `id` (oriented by the map's normal for a surface species); `map`
// must hold the candidate's voxel.
void addBirth(const Model& model, const GradientMap& map, Particles& p, int species, const BirthCandidate& c,
              std::uint64_t id);

// Whether some position in `pos` lies closer than `distance` to x (the periodic axes of `box`
// wrap): a seed there would sit on a particle, where the pair forces have no bound, so it is not
// placed (its id is still counted, as on the ranks that do not own it). So is a seed near an
// earlier seed of the same step, placed or not: every rank of a decomposed run decides alike.
bool crowded(const std::vector<Eigen::Vector3d>& pos, const Box& box, const Eigen::Vector3d& x, double distance);

// The default seed of a species among the voxels of `map` whose centre `mine` accepts: a surface
// voxel chosen by the hash, or the deepest volume voxel. (key, position) of the best one, the
// smaller key being better; nullopt if none.
struct SeedChoice {
    std::pair<long long, std::uint64_t> key;  // (-depth^2 or 0, hash)
    Eigen::Vector3d pos;                      // voxel centre, simulation length units
};
std::optional<SeedChoice> defaultSeed(const ConstructionParams& params, const Model& model, const GradientMap& map,
                                      int species, const std::function<bool(const Eigen::Vector3d&)>& mine);
// The same choice within each piece of the species' voxels: piece[v] numbers the piece of map
// voxel v from 1 (0: in none); entry k - 1 is piece k's seed (none when it has no voxel of the
// species). A piece holding every voxel of the species gets defaultSeed's voxel.
std::vector<std::optional<SeedChoice>> seedsOfPieces(const ConstructionParams& params, const Model& model,
                                                     const GradientMap& map, int species,
                                                     const std::vector<std::uint32_t>& piece, std::uint32_t pieces);

}  // namespace bop::core
