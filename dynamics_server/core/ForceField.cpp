#include "ForceField.hpp"

#include "Threads.hpp"

#include <chrono>

namespace bop::core {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

float ForceField::curvatureWeight(const Model& model, const Eigen::Vector3d& x, int species) {
    if (!model.map || !model.isSurface(species)) return 1.0f;
    const GradientMap& map = *model.map;
    const double h = voxelLength(map.r0Voxels);
    return map.nearestSurface(map.voxelAt((x / h).array().floor().cast<int>().matrix())).cpWeight;
}

ForceField::ForceField(const Model& model)
    : kernel_(model),
      isVolume_(std::size_t(model.speciesCount()) + 1, 0),
      isWide_(std::size_t(model.speciesCount()) + 1, 0),
      oriented_(kernel_.anyOriented()),
      skin_(model.integration.skinR0 * kR0),
      prune_(model.integration.pruneR0 < model.integration.skinR0 ? model.integration.pruneR0 * kR0 : 0.0) {
    for (int s = 1; s <= model.speciesCount(); ++s) {
        isVolume_[std::size_t(s)] = !model.isSurface(s);
        isWide_[std::size_t(s)] = oriented_ && kernel_.orientedSpecies(s);
    }
}

double ForceField::listRange() const {
    const double lj = kernel_.lj().cutoff() + skin_;
    return oriented_ ? std::max(lj, kernel_.weight().cutoff() + skin_) : lj;
}

double ForceField::listRange(const Model& model) {
    const PairKernel kernel(model);
    const double skin = model.integration.skinR0 * kR0, lj = kernel.lj().cutoff() + skin;
    return kernel.anyOriented() ? std::max(lj, kernel.weight().cutoff() + skin) : lj;
}

void ForceField::setParams(const Model& model) {
    const std::vector<char> wideBefore = isWide_;
    const double ljCutBefore = kernel_.lj().cutoff(), wideCutBefore = kernel_.weight().cutoff();
    const bool orientedBefore = oriented_;
    kernel_ = PairKernel(model);
    oriented_ = kernel_.anyOriented();
    for (int s = 1; s <= model.speciesCount(); ++s) isWide_[std::size_t(s)] = oriented_ && kernel_.orientedSpecies(s);
    if (oriented_ != orientedBefore || isWide_ != wideBefore || kernel_.lj().cutoff() != ljCutBefore ||
        kernel_.weight().cutoff() != wideCutBefore)
        requestRebuild();
}

void ForceField::compute(const Model& model, const ProbeState& probe, Particles& p, ForceStats& stats,
                         PhaseTimes* times, bool energies, const Halo* halo) {
    static const std::vector<Eigen::Vector3d> kNoHalo;
    const std::vector<Eigen::Vector3d>& haloPos = halo ? halo->pos : kNoHalo;
    stats = ForceStats{};
    forEachIndex(p.size(), [&](std::size_t i) {
        p.force[i].setZero();
        p.torque[i].setZero();
    });
    auto t0 = Clock::now();
    gradientMapForces(model, p, stats);
    if (times) times->gradientMap += since(t0);
    t0 = Clock::now();
    const bool held = heldSinceCompute_;
    heldSinceCompute_ = false;
    if (p.revision != revision_ || !(held || list_.measure(model.box, p.pos, 0.5 * skin_))) {
        if (oriented_) {  // the oriented terms' pairs: surface particles with weights, to their cutoff
            wide_.range = kernel_.weight().cutoff() + skin_;
            wide_.member.resize(p.size() + haloPos.size());
            for (std::size_t i = 0; i < p.size(); ++i) wide_.member[i] = isWide_[p.species[i]];
            for (std::size_t g = 0; g < haloPos.size(); ++g) wide_.member[p.size() + g] = isWide_[halo->species[g]];
        }
        list_.build(model.box, kernel_.lj().cutoff() + skin_, p.pos, haloPos, oriented_ ? &wide_ : nullptr);
        list_.measure(model.box, p.pos, 0.5 * skin_);
        revision_ = p.revision;
    }
    list_.move(haloPos);
    // Half the inner skin, less a margin for rounding: a dropped pair stays beyond its cutoff.
    if (prune_ > 0 && !pruned_.holds(list_))
        pruned_.prune(list_, kernel_.lj().cutoff() + prune_, kernel_.weight().cutoff() + prune_,
                      0.5 * prune_ * (1.0 - 1e-9));
    if (times) times->neighbours += since(t0);
    t0 = Clock::now();
    gatherEntries(model, p, halo);
    pairForces(p, halo, stats, energies, times);
    if (times) times->pairs += since(t0);
    t0 = Clock::now();
    probeForces(model, probe, p, stats);
    if (times) times->probe += since(t0);
}

bool ForceField::listHolds(const Model& model, const Particles& p) {
    heldSinceCompute_ = p.revision == revision_ && list_.measure(model.box, p.pos, 0.5 * skin_);
    return heldSinceCompute_;
}

void ForceField::gradientMapForces(const Model& model, Particles& p, ForceStats& stats) {
    if (oriented_) cpWeight_.assign(p.size(), 1.0f);  // curvature weights serve the co-planar pairs only
    if (!model.map) return;
    if (fieldMap_ != model.map) {
        field_ = std::make_unique<core::GmField>(*model.map, model.interpolation);
        fieldMap_ = model.map;
    }
    if (blendMap_ && blendFieldMap_ != blendMap_) {
        blendField_ = std::make_unique<core::GmField>(*blendMap_, model.interpolation);
        blendFieldMap_ = blendMap_;
    }
    const double w = blendMap_ ? blendW_ : 0.0;
    const Dims& whole = model.map->wholeDims();
    const Eigen::Vector3d centre = 0.5 * Eigen::Vector3d(whole.nx, whole.ny, whole.nz) * field_->voxelSize();
    stats.wallVirial = sumIndex(p.size(), [&](std::size_t i) {  // each particle on its own: on the threads
        const Species& sp = model.species[p.species[i]];
        core::GmSample g = field_->sample(sp.kind, p.species[i], p.pos[i], p.normal[i]);
        if (w > 0) {  // keyframes: on the way to the next frame's shape
            const core::GmSample n = blendField_->sample(sp.kind, p.species[i], p.pos[i], p.normal[i]);
            g.force = (1 - w) * g.force + w * n.force;
            g.torque = (1 - w) * g.torque + w * n.torque;
        }
        p.force[i] += sp.alphaForceGm * g.force;
        if (sp.kind == ParticleKind::Surface) {
            p.torque[i] += sp.alphaTorqueGm * g.torque;
            if (oriented_) cpWeight_[i] = g.cpWeight;  // curvatureWeight(), from the same voxel
            return 0.0;
        }
        return (p.pos[i] - centre).dot(sp.alphaForceGm * g.force);
    });
}

void ForceField::gatherEntries(const Model& model, const Particles& p, const Halo* halo) {
    const auto& owner = list_.owner();
    const std::size_t ne = list_.entryCount(), n = p.size();
    if (speciesBuild_ != list_.builds()) {  // entries change only when the list is built
        ss_.resize(ne);
        for (std::size_t k = 0; k < ne; ++k) ss_[k] = owner[k] < n ? p.species[owner[k]] : halo->species[owner[k] - n];
        speciesBuild_ = list_.builds();
    }
    if (!oriented_) return;
    sn_.resize(ne);
    sw_.resize(ne);
    for (std::size_t k = 0; k < ne; ++k) {
        if (owner[k] < n) {
            sn_[k] = p.normal[owner[k]];
            sw_[k] = cpWeight_[owner[k]];
        } else {
            sn_[k] = halo->normal[owner[k] - n];
            sw_[k] = curvatureWeight(model, halo->pos[owner[k] - n], halo->species[owner[k] - n]);
        }
    }
}

void ForceField::pairForces(Particles& p, const Halo* halo, ForceStats& stats, bool energies, PhaseTimes* times) {
    const auto& owner = list_.owner();
    const std::size_t ne = list_.entryCount(), n = p.size();
    sf_.resize(ne);
    if (oriented_) st_.resize(ne);
    if (chunkedBuild_ != list_.builds()) chunks_.plan(list_, oriented_), chunkedBuild_ = list_.builds();
    // Pairs within the subdomain count whole, pairs with halo ghosts by half (the ghost's owner
    // counts the other half).
    PairKernel::Sums sums, haloSums;
    const PairInputs in{list_.positions().data(), ss_.data(), isVolume_.data(), sf_.data()};
    const OrientedInputs o{sn_.data(), sw_.data(), st_.data()};
    double loopSeconds[2] = {0, 0};
    const PrunedPairs::Sets sets = prune_ > 0 ? pruned_.sets() : PrunedPairs::whole(list_);
    chunks_.run(kernel_, sets, in, o, energies, halo != nullptr, sums, haloSums, loopSeconds);
    // Forces on images go to their particles; forces on halo ghosts are their owners' business.
    for (std::size_t k = 0; k < ne; ++k)
        if (owner[k] < n) p.force[owner[k]] += sf_[k];
    if (oriented_)
        for (std::size_t k = 0; k < ne; ++k)
            if (owner[k] < n) p.torque[owner[k]] += st_[k];
    stats.pairEnergy = energies ? sums.energy + 0.5 * haloSums.energy : 0.0;
    stats.virial = sums.virial + 0.5 * haloSums.virial;
    stats.virialVolume = sums.virialVolume + 0.5 * haloSums.virialVolume;
    stats.pairsInRange = sums.inRange + haloSums.inRange;
    stats.orientedPairsInRange = sums.orientedInRange + haloSums.orientedInRange;
    if (times) {
        times->ljLoopSeconds += loopSeconds[0];
        times->orientedLoopSeconds += loopSeconds[1];
        times->ljPairs += double(stats.pairsInRange);
        times->orientedPairs += double(stats.orientedPairsInRange);
    }
}

void ForceField::computePairsBruteForce(const Model& model, Particles& p, ForceStats& stats) {
    const PairKernel kernel(model);
    std::vector<float> w(p.size(), 1.0f);
    for (std::size_t i = 0; i < p.size(); ++i) w[i] = curvatureWeight(model, p.pos[i], p.species[i]);
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

void ForceField::probeForces(const Model& model, const ProbeState& probe, Particles& p, ForceStats& stats) {
    if (!probe.active) return;
    const ProbeForm form(LjForm(model.ljParams), probe.params);
    const double cut2 = form.cutoff() * form.cutoff();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector3d r = p.pos[i] - probe.position;
        const double r2 = r.squaredNorm();
        if (r2 >= cut2) continue;
        double fOverR, e;
        if (!form.eval(r2, fOverR, e)) continue;
        p.force[i] += fOverR * r;
        stats.probeReaction -= fOverR * r;
        stats.probeEnergy += e;
    }
}

}  // namespace bop::core
