// Construction in a decomposed run (see DecomposedSimulation.hpp): each rank checks its own
// subdomain, the ranks gather what they found, and every rank makes the same choice.
#include "DecomposedSimulation.hpp"

#include "Packing.hpp"
#include "core/ConstructionSteps.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace bop::parallel {
namespace {

// Particles of every species over all ranks (whole numbers: exact in any order).
std::vector<std::size_t> speciesCounts(const CartComm& comm, const core::Particles& p, int speciesCount) {
    std::vector<double> mine(std::size_t(speciesCount) + 1, 0.0);
    for (auto s : p.species) mine[s] += 1;
    const std::vector<double> all = comm.allGather(mine);
    std::vector<std::size_t> count(mine.size(), 0);
    for (std::size_t k = 0; k < all.size(); ++k) count[k % mine.size()] += std::size_t(all[k]);
    return count;
}

std::vector<core::DeathMark> gatherMarks(const CartComm& comm, const std::vector<core::DeathMark>& marks) {
    std::vector<double> out;
    for (const auto& m : marks) out.insert(out.end(), {idBits(m.key), idBits(m.id), double(m.species)});
    const std::vector<double> in = comm.allGatherV(out);
    std::vector<core::DeathMark> all;
    for (std::size_t k = 0; k + 3 <= in.size(); k += 3) all.push_back({idOf(in[k]), idOf(in[k + 1]), int(in[k + 2])});
    return all;
}

std::vector<core::BirthCandidate> gatherCandidates(const CartComm& comm, const std::vector<core::BirthCandidate>& c) {
    std::vector<double> out;
    for (const auto& b : c) out.insert(out.end(), {b.pos.x(), b.pos.y(), b.pos.z(), idBits(b.key), idBits(b.voxel)});
    const std::vector<double> in = comm.allGatherV(out);
    std::vector<core::BirthCandidate> all;
    for (std::size_t k = 0; k + 5 <= in.size(); k += 5)
        all.push_back({Eigen::Vector3d(in[k], in[k + 1], in[k + 2]), idOf(in[k + 3]), idOf(in[k + 4])});
    return all;
}

void removeIds(core::Particles& p, const std::vector<std::uint64_t>& sortedIds) {
    std::vector<char> flag(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i) flag[i] = std::binary_search(sortedIds.begin(), sortedIds.end(), p.id[i]);
    p.removeIf(flag);
}

}  // namespace

Eigen::Vector3d DecomposedSimulation::defaultSeed(int species) const {
    if (!sub_.map) throw std::invalid_argument("seeding needs a gradient map");
    const auto best = core::defaultSeed(construction_.params(), sub_, species, [&](const Eigen::Vector3d& x) { return mine(x); });
    const std::vector<double> all = comm_.allGather(
        best ? std::vector<double>{1.0, double(best->key.first), idBits(best->key.second), best->pos.x(), best->pos.y(), best->pos.z()}
             : std::vector<double>(6, 0.0));
    std::optional<core::SeedChoice> choice;
    for (std::size_t k = 0; k < all.size(); k += 6) {
        if (all[k] == 0) continue;
        const core::SeedChoice c{{(long long)(all[k + 1]), idOf(all[k + 2])}, Eigen::Vector3d(all[k + 3], all[k + 4], all[k + 5])};
        if (!choice || c.key < choice->key) choice = c;
    }
    if (!choice) throw std::invalid_argument("species " + std::to_string(species) + " has no voxels in the map");
    return choice->pos;
}

void DecomposedSimulation::construct(std::vector<core::ConstructionEvent> events) {
    core::ConstructionCounts built;  // over all ranks
    bool changed = false;
    std::vector<Eigen::Vector3d> seeded;  // this step's seeds, placed or not: every rank knows them
    for (const auto& e : events) {
        if (e.action != core::ConstructionEvent::Action::Seed) {
            construction_.setBirth(e.species, e.action == core::ConstructionEvent::Action::BirthOn);
            continue;
        }
        const double h = mapSource_ ? core::kR0 / mapSource_->header.r0Voxels : 1.0;
        const Eigen::Vector3d x = e.positionVoxels ? Eigen::Vector3d(*e.positionVoxels * h) : defaultSeed(e.species);
        const double near = construction_.params().deathR0 * core::kR0;  // the halo reaches further
        const bool free = !core::crowded(p_.pos, model_->box, x, near) && !core::crowded(halo_.pos, model_->box, x, near) &&
                          !core::crowded(seeded, model_->box, x, near);
        construction_.seed(sub_, p_, e.species, x, step_, mine(x) && free);  // every rank counts the seed
        seeded.push_back(x);
        changed = true;
    }
    if (construction_.checkDue(step_)) {
        changed = true;
        const core::ConstructionParams& params = construction_.params();
        // Every particle within the birth front of this subdomain, at today's positions.
        migrateHome();
        buildHalo(std::max(range_, params.frontR0 * core::kR0));
        core::Particles seen = p_;
        for (std::size_t g = 0; g < halo_.size(); ++g) seen.add(halo_.pos[g], halo_.species[g], halo_.id[g]);
        const std::size_t owned = p_.size();

        std::vector<std::size_t> count = speciesCounts(comm_, p_, sub_.speciesCount());
        const std::vector<std::uint64_t> die = core::chooseDeaths(
            params, gatherMarks(comm_, core::markDeaths(params, {sub_, sub_.box, seen, owned}, step_)), count,
            construction_.birthSwitches());
        removeIds(p_, die);
        removeIds(seen, die);
        built.deaths = die.size();

        count = speciesCounts(comm_, p_, sub_.speciesCount());
        for (int s = 1; sub_.map && s <= sub_.speciesCount(); ++s) {
            if (!construction_.birthOn(s) || count[std::size_t(s)] == 0) continue;  // births grow from a seed
            const auto found = core::birthCandidates(params, {sub_, sub_.box, seen, p_.size()}, s, step_,
                                                     [&](const Eigen::Vector3d& x) { return mine(x); });
            const auto winners = core::chooseBirths(params, model_->box, gatherCandidates(comm_, found), count[std::size_t(s)]);
            for (const auto& w : winners) {
                if (mine(w.pos)) core::addBirth(sub_, p_, s, w, step_);
                // Every newborn blocks later species' births nearby, here too; across a periodic
                // seam that other ranks hold, as the image this rank's halo would show.
                for (int image = 0; image < 27; ++image) {
                    Eigen::Vector3d x = w.pos;
                    bool valid = true;
                    for (int a = 0, code = image; a < 3; ++a, code /= 3) {
                        const int shift = code % 3 - 1;
                        if (shift == 0) continue;
                        valid = valid && model_->box.periodic[std::size_t(a)] && comm_.dims()[std::size_t(a)] > 1;
                        x[a] += shift * model_->box.size()[a];
                    }
                    if (valid) seen.add(x, s, core::birthId(step_, w.voxel));
                }
            }
            built.births += winners.size();
        }
    }
    if (!changed) return;
    construction_.addToTotals(built);
    // The particles changed: new halo (and cut planes, as a growing bag needs them), new list,
    // forces for the newborn (as a single process does).
    if (imbalanceNow() > 1.1) {
        rebalance();
    } else {
        buildHalo(range_);
        field_.requestRebuild();
    }
    forces(true);
}

}  // namespace bop::parallel
