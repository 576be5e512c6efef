#include "PairForces.hpp"

#include "MapForces.hpp"
#include "Stopwatch.hpp"
#include "Threads.hpp"

namespace bop::core {

PairForces::PairForces(const Model& model, const Params& params, bool map)
    : kernel_(model, params, map),
      isVolume_(std::size_t(model.speciesCount()) + 1, 0),
      isWide_(std::size_t(model.speciesCount()) + 1, 0),
      oriented_(kernel_.anyOriented()),
      map_(map),
      mixed_(model.integration.mixedPrecision),
      skin_(model.integration.skinR0 * kR0),
      prune_(model.integration.pruneR0 < model.integration.skinR0 ? model.integration.pruneR0 * kR0 : 0.0) {
    for (int s = 1; s <= model.speciesCount(); ++s) {
        isVolume_[std::size_t(s)] = !model.isSurface(s);
        isWide_[std::size_t(s)] = oriented_ && kernel_.orientedSpecies(s);
    }
}

double PairForces::listRange() const {
    const double lj = kernel_.lj().cutoff() + skin_;
    return oriented_ ? std::max(lj, kernel_.weight().cutoff() + skin_) : lj;
}

double PairForces::listRange(const Model& model, const Params& params) {
    return PairForces(model, params, false).listRange();
}

void PairForces::setParams(const Model& model, const Params& params) {
    const std::vector<char> wideBefore = isWide_;
    const double ljCutBefore = kernel_.lj().cutoff(), wideCutBefore = kernel_.weight().cutoff();
    const bool orientedBefore = oriented_;
    kernel_ = PairKernel(model, params, map_);
    oriented_ = kernel_.anyOriented();
    for (int s = 1; s <= model.speciesCount(); ++s) isWide_[std::size_t(s)] = oriented_ && kernel_.orientedSpecies(s);
    if (oriented_ != orientedBefore || isWide_ != wideBefore || kernel_.lj().cutoff() != ljCutBefore ||
        kernel_.weight().cutoff() != wideCutBefore)
        requestRebuild();
}

bool PairForces::listHolds(const Box& region, const Particles& p) {
    heldSinceCompute_ = p.revision == revision_ && list_.measure(region, p.pos, 0.5 * skin_);
    return heldSinceCompute_;
}

void PairForces::updateList(const Box& region, const Particles& p, const Halo* halo) {
    static const std::vector<Eigen::Vector3d> kNoHalo;
    const std::vector<Eigen::Vector3d>& haloPos = halo ? halo->pos : kNoHalo;
    const bool held = heldSinceCompute_;
    heldSinceCompute_ = false;
    if (p.revision != revision_ || !(held || list_.measure(region, p.pos, 0.5 * skin_))) {
        if (oriented_) {  // the oriented terms' pairs: surface particles with weights, to their cutoff
            wide_.range = kernel_.weight().cutoff() + skin_;
            wide_.member.resize(p.size() + haloPos.size());
            forEachIndex(p.size(), [&](std::size_t i) { wide_.member[i] = isWide_[p.species[i]]; });
            for (std::size_t g = 0; g < haloPos.size(); ++g) wide_.member[p.size() + g] = isWide_[halo->species[g]];
            // Only the pairs with oriented weights: not two bags' surfaces.
            wide_.side = std::size_t(kernel_.tableSide());
            const char* on = kernel_.orientedTables().on;
            wide_.together.assign(on, on + wide_.side * wide_.side);
            wide_.group.resize(wide_.member.size());
            forEachIndex(p.size(), [&](std::size_t i) { wide_.group[i] = p.species[i]; });
            for (std::size_t g = 0; g < haloPos.size(); ++g) wide_.group[p.size() + g] = halo->species[g];
        }
        keys_ = p.id;  // entries by id within a cell: the list does not depend on the particles' order
        if (halo) keys_.insert(keys_.end(), halo->id.begin(), halo->id.end());
        keys_.resize(p.size() + haloPos.size());
        list_.build(region, kernel_.lj().cutoff() + skin_, p.pos, haloPos, oriented_ ? &wide_ : nullptr, &keys_,
                    kernel_.lj().cutoff());
        list_.measure(region, p.pos, 0.5 * skin_);
        revision_ = p.revision;
    }
    list_.move(haloPos);
    // Half the inner skin, less a margin for rounding: a dropped pair stays beyond its cutoff.
    if (prune_ > 0 && !pruned_.holds(list_))
        pruned_.prune(list_, kernel_.lj().cutoff() + prune_, kernel_.weight().cutoff() + prune_,
                      0.5 * prune_ * (1.0 - 1e-9));
}

void PairForces::gatherEntries(const Model& model, const GradientMap* map, const Particles& p, const Halo* halo,
                               const std::vector<float>& curvature) {
    const auto& owner = list_.owner();
    const std::size_t ne = list_.entryCount(), n = p.size();
    PairEntries& e = entries_;
    if (speciesBuild_ != list_.builds()) {  // entries change only when the list is built
        e.species.resize(ne);
        forEachIndex(ne, [&](std::size_t k) {
            e.species[k] = owner[k] < n ? p.species[owner[k]] : halo->species[owner[k] - n];
        });
        speciesBuild_ = list_.builds();
    }
    e.force.resize(ne);
    if (!oriented_) return;
    e.torque.resize(ne);
    e.normal.resize(ne);
    e.curvature.resize(ne);
    forEachIndex(ne, [&](std::size_t k) {  // each entry on its own: on the threads
        if (owner[k] < n) {
            e.normal[k] = p.normal[owner[k]];
            e.curvature[k] = curvature[owner[k]];
        } else {
            const std::size_t g = owner[k] - n;
            e.normal[k] = halo->normal[g];
            e.curvature[k] = MapForces::curvatureWeight(model, map, halo->pos[g], halo->species[g]);
        }
    });
}

void PairForces::add(const Model& model, const MapInForce& maps, Particles& p, const Halo* halo,
                     const std::vector<float>& curvature, ForceStats& stats, bool energies, PhaseTimes* times) {
    auto t0 = PhaseClock::now();
    updateList(maps.region, p, halo);
    if (times) times->neighbours += secondsSince(t0);
    t0 = PhaseClock::now();
    gatherEntries(model, maps.map().get(), p, halo, curvature);
    if (chunkedBuild_ != list_.builds()) chunks_.plan(list_, oriented_), chunkedBuild_ = list_.builds();
    // Pairs within the subdomain count whole, pairs with halo ghosts by half (the ghost's owner
    // counts the other half).
    PairKernel::Sums sums, haloSums;
    PairEntries& e = entries_;
    const PairInputs in{list_.positions().data(), e.species.data(), isVolume_.data(), e.force.data(), 0, mixed_};
    const OrientedInputs o{e.normal.data(), e.curvature.data(), e.torque.data()};
    double loopSeconds[2] = {0, 0};
    const PrunedPairs::Sets sets = prune_ > 0 ? pruned_.sets() : PrunedPairs::whole(list_);
    // Forces on images go to their particles; forces on halo ghosts are their owners' business.
    // Without images or ghosts each particle has one entry, and the chunks add to it directly;
    // else each particle's entry that is not an image on the threads, then the images in entry order.
    const auto& owner = list_.owner();
    const bool direct = list_.ghostCount() == 0;
    ParticleTargets into;
    if (direct) into = {p.force.data(), oriented_ ? p.torque.data() : nullptr, owner.data()};
    chunks_.run(kernel_, sets, in, o, energies, halo != nullptr, sums, haloSums, loopSeconds, into);
    if (!direct) {
        const auto& image = list_.images();
        const std::size_t ne = list_.entryCount(), n = p.size();
        const auto fold = [&](std::size_t k) {
            p.force[owner[k]] += e.force[k];
            if (oriented_) p.torque[owner[k]] += e.torque[k];
        };
        forEachIndex(ne, [&](std::size_t k) {
            if (owner[k] < n && !image[k]) fold(k);
        });
        for (std::size_t k = 0; k < ne; ++k)
            if (owner[k] < n && image[k]) fold(k);
    }
    stats.pairEnergy = energies ? sums.energy + 0.5 * haloSums.energy : 0.0;
    stats.virial = sums.virial + 0.5 * haloSums.virial;
    stats.virialVolume = sums.virialVolume + 0.5 * haloSums.virialVolume;
    stats.pairsInRange = sums.inRange + haloSums.inRange;
    stats.orientedPairsInRange = sums.orientedInRange + haloSums.orientedInRange;
    if (times) {
        times->pairs += secondsSince(t0);
        times->ljLoopSeconds += loopSeconds[0];
        times->orientedLoopSeconds += loopSeconds[1];
        times->ljPairs += double(stats.pairsInRange);
        times->orientedPairs += double(stats.orientedPairsInRange);
    }
}

void PairForces::bruteForce(const Model& model, const Params& params, Particles& p, ForceStats& stats) {
    const PairKernel kernel(model, params, model.map != nullptr);
    std::vector<float> w(p.size(), 1.0f);
    for (std::size_t i = 0; i < p.size(); ++i)
        w[i] = MapForces::curvatureWeight(model, model.map.get(), p.pos[i], p.species[i]);
    PairKernel::Sums sums;
    const Eigen::Vector3d L = model.box.size();
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            Eigen::Vector3d r = p.pos[j] - p.pos[i];
            for (int a = 0; a < 3; ++a)
                if (model.box.periodic[std::size_t(a)]) r[a] -= L[a] * std::round(r[a] / L[a]);
            kernel.apply(i, j, p.species[i], p.species[j], r, r.squaredNorm(), p.normal[i], p.normal[j], w[i], w[j],
                         p.force.data(), p.torque.data(), !model.isSurface(p.species[i]),
                         !model.isSurface(p.species[j]), sums);
        }
    stats.pairEnergy = sums.energy;
    stats.virial = sums.virial;
    stats.virialVolume = sums.virialVolume;
    stats.pairsInRange = sums.inRange;
    stats.orientedPairsInRange = sums.orientedInRange;
}

}  // namespace bop::core
