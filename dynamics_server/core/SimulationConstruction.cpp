// Construction in a step (paper §3.6, docs/physics.md §7; Simulation.hpp): each process checks its
// own region against its particles and the ghosts within the birth front, the processes gather
// what they found, and every one makes the same choice (caps, conflicts), as one process makes it
// over all the particles; the owner of each position adds the particle.
#include "ConstructionSteps.hpp"
#include "Simulation.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace bop::core {
namespace {

// Particles of every species over all processes.
std::vector<std::size_t> speciesCounts(Exchange& ex, const Particles& p, int speciesCount) {
    std::vector<std::uint64_t> mine(std::size_t(speciesCount) + 1, 0);
    for (auto s : p.species) mine[s] += 1;
    const std::vector<std::uint64_t> all = ex.allGather(mine);
    std::vector<std::size_t> count(mine.size(), 0);
    for (std::size_t k = 0; k < all.size(); ++k) count[k % mine.size()] += std::size_t(all[k]);
    return count;
}

std::vector<DeathMark> gatherMarks(Exchange& ex, const std::vector<DeathMark>& marks) {
    return ex.size() == 1 ? marks : ex.allGatherV(marks);
}

std::vector<BirthCandidate> gatherCandidates(Exchange& ex, std::vector<BirthCandidate> c) {
    return ex.size() == 1 ? c : ex.allGatherV(c);
}

// A process's best default seed, if it has one (Simulation::defaultSeed).
struct SeedOffer {
    std::int32_t found = 0;
    long long depthKey = 0;
    std::uint64_t hash = 0;
    Eigen::Vector3d pos = Eigen::Vector3d::Zero();
};

void removeIds(Particles& p, const std::vector<std::uint64_t>& sortedIds) {
    if (sortedIds.empty()) return;  // not even a new revision: the neighbour list holds
    std::vector<char> flag(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i)
        flag[i] = std::binary_search(sortedIds.begin(), sortedIds.end(), p.id[i]);
    p.removeIf(flag);
}

}  // namespace

Eigen::Vector3d Simulation::defaultSeed(int species) const {
    if (!maps_.map()) throw std::invalid_argument("seeding needs a gradient map");
    const auto best = core::defaultSeed(construction_.params(), *model_, *maps_.map(), species,
                                        [&](const Eigen::Vector3d& x) { return ex_->owns(x); });
    const std::vector<SeedOffer> all =
        ex_->allGather(std::vector{best ? SeedOffer{1, best->key.first, best->key.second, best->pos} : SeedOffer{}});
    std::optional<SeedChoice> choice;
    for (const SeedOffer& o : all) {
        if (!o.found) continue;
        const SeedChoice c{{o.depthKey, o.hash}, o.pos};
        if (!choice || c.key < choice->key) choice = c;
    }
    if (!choice) throw std::invalid_argument("species " + std::to_string(species) + " has no voxels in the map");
    return choice->pos;
}

void Simulation::construct(std::vector<ConstructionEvent> events) {
    const long long step = stats_.step;
    stats_.built = {};
    if (events.empty() && !construction_.checkDue(step)) return;  // every process knows both: no message
    ConstructionCounts built;                                     // over all processes
    bool changed = false;                                         // this process's particles
    bool moved = false;  // particles migrated (wrapped into the box) or ghosts widened to the birth front
    std::vector<Eigen::Vector3d> seeded;  // this step's seeds, placed or not: every process knows them
    for (const auto& e : events) {
        if (e.action != ConstructionEvent::Action::Seed) {
            construction_.setBirth(e.species, e.action == ConstructionEvent::Action::BirthOn);
            continue;
        }
        const double h = maps_.map() ? voxelLength(maps_.map()->r0Voxels) : 1.0;
        const Eigen::Vector3d x = e.positionVoxels ? Eigen::Vector3d(*e.positionVoxels * h) : defaultSeed(e.species);
        const double near = construction_.params().deathR0 * kR0;  // the ghosts reach further
        const bool free = !crowded(p_.pos, model_->box, x, near) && !crowded(halo_.pos, model_->box, x, near) &&
                          !crowded(seeded, model_->box, x, near);
        const std::size_t before = p_.size();
        construction_.seed(*model_, maps_.map().get(), p_, e.species, x,
                           ex_->owns(x) && free);  // every process counts the seed
        changed = changed || p_.size() != before;
        seeded.push_back(x);
    }
    if (construction_.checkDue(step)) {
        const ConstructionParams& params = construction_.params();
        // Every particle within the birth front of this region, at today's positions, in the box.
        moved = ex_->widen(p_, halo_, std::max(range_, params.frontR0 * kR0));
        Particles seen = p_;
        for (std::size_t g = 0; g < halo_.size(); ++g) seen.add(halo_.pos[g], halo_.species[g], halo_.id[g]);
        const std::size_t owned = p_.size();

        std::vector<std::size_t> count = speciesCounts(*ex_, p_, model_->speciesCount());
        const std::vector<std::uint64_t> die = chooseDeaths(
            params,
            gatherMarks(*ex_, markDeaths(params, {*model_, maps_.region, seen, owned, maps_.map().get()}, step)), count,
            construction_.birthSwitches());
        removeIds(p_, die);
        removeIds(seen, die);
        built.deaths = die.size();

        count = speciesCounts(*ex_, p_, model_->speciesCount());
        for (int s = 1; maps_.map() && s <= model_->speciesCount(); ++s) {
            if (!construction_.birthOn(s) || count[std::size_t(s)] == 0) continue;  // births grow from a seed
            const auto found = birthCandidates(params, {*model_, maps_.region, seen, p_.size(), maps_.map().get()}, s,
                                               step, [&](const Eigen::Vector3d& x) { return ex_->owns(x); });
            const auto winners =
                chooseBirths(params, model_->box, gatherCandidates(*ex_, found), count[std::size_t(s)]);
            const std::uint64_t firstId = construction_.takeIds(winners.size());  // in the winners' order
            for (std::size_t k = 0; k < winners.size(); ++k) {
                const BirthCandidate& w = winners[k];
                const std::uint64_t id = firstId + k;
                if (ex_->owns(w.pos)) addBirth(*model_, *maps_.map(), p_, s, w, id);
                // Every newborn blocks later species' births nearby, here too; across a periodic
                // seam that other processes hold, as the image this process's ghosts would show.
                for (int image = 0; image < 27; ++image) {
                    Eigen::Vector3d x = w.pos;
                    bool valid = true;
                    for (int a = 0, code = image; a < 3; ++a, code /= 3) {
                        const int shift = code % 3 - 1;
                        if (shift == 0) continue;
                        valid = valid && model_->box.periodic[std::size_t(a)] && ex_->splitsAxis(a);
                        x[a] += shift * model_->box.size()[a];
                    }
                    if (valid) seen.add(x, s, id);
                }
            }
            built.births += winners.size();
        }
        changed = changed || built.births > 0 || built.deaths > 0;
    }
    construction_.addToTotals(built);
    stats_.built = built;
    // New particles anywhere (or moved, or ghosts widened for the check): new ghosts, and cut
    // planes as a growing bag needs them, a new list and forces for the newborn, as one process
    // makes them.
    if (ex_->allTrue(!changed) && !moved) return;
    placeRegion(ex_->afterChange(p_, halo_, range_));
    forcesStale_ = true;
}

}  // namespace bop::core
