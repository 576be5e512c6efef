// A cut in a step (CutCommand, docs/physics.md §9): the map follows (every keyframe's window is
// patched by bop::cutPatch, the same patch on every process, kept to patch the windows a moved
// region reads later), then the particles: those in the swept volume leave, a volume particle
// left on a new face becomes a surface particle with the map's normal, a bonded bag's bonds
// across the blade break (Bonds.hpp breakBonds), and the births of the cut bags' surfaces go on
// so that their faces close.
#include "Integrator.hpp"
#include "Simulation.hpp"
#include "Stopwatch.hpp"

#include <algorithm>
#include <stdexcept>

namespace bop::core {
namespace {

bop::BladeSweep sweepOf(const CutCommand& c, double h) {
    bop::BladeSweep b;
    b.a = c.from / h;
    b.b = c.to / h;
    b.radius = c.radius / h;
    return b;
}

struct CutSums {
    double removed = 0, converted = 0;
};

}  // namespace

void Simulation::checkCut(const CutCommand& c) const {
    if (!maps_.map()) throw std::invalid_argument("cut command: the run has no gradient map to cut");
    if (!c.from.allFinite() || !c.to.allFinite() || !std::isfinite(c.radius) || c.radius <= 0)
        throw std::invalid_argument("cut command: expected finite end points and a radius above 0");
}

bop::GradientMap Simulation::patched(std::size_t frame, bop::GradientMap window) const {
    if (frame < patches_.size())
        for (const bop::MapPatch& p : patches_[frame]) window = bop::applyPatch(window, p);
    return window;
}

std::vector<int> Simulation::patchMaps(const PatchMaker& make) {
    patches_.resize(maps_.frames.size());
    // Every keyframe's patch first: an edit refused for one (std::domain_error) changes none.
    std::vector<bop::MapPatch> made(maps_.frames.size());
    for (std::size_t f = 0; f < maps_.frames.size(); ++f) {
        const GradientMap& held = *maps_.frames[f];
        const Eigen::Vector3i heldHi = held.origin + Eigen::Vector3i(held.dims().nx, held.dims().ny, held.dims().nz);
        const auto read = [&](const bop::VoxelWindow& w) {
            if ((w.lo.array() >= held.origin.array()).all() && (w.hi.array() <= heldHi.array()).all())
                return bop::cropGradientMap(held, w);
            // Beyond this process's window: the source's, with every edit so far.
            if (mapSource_) return patched(f, mapSource_->crop(int(f), w));
            const auto& whole = model_->frames.size() > 1 ? model_->frames[f] : model_->map;
            return patched(f, bop::cropGradientMap(*whole, w));
        };
        made[f] = make(read, held);
    }
    std::vector<int> bags;
    for (std::size_t f = 0; f < maps_.frames.size(); ++f) {
        bop::MapPatch& patch = made[f];
        if (patch.empty()) continue;
        for (int b : patch.bags)
            if (std::find(bags.begin(), bags.end(), b) == bags.end()) bags.push_back(b);
        maps_.frames[f] = std::make_shared<const GradientMap>(bop::applyPatch(*maps_.frames[f], patch));
        patches_[f].push_back(std::move(patch));
    }
    return bags;
}

std::vector<int> Simulation::editMaps(const CutCommand& c) {
    const bop::BladeSweep blade = sweepOf(c, voxelLength(maps_.map()->r0Voxels));
    const std::vector<int> bags = patchMaps([&](const bop::MapWindowReader& read, const GradientMap& held) {
        return bop::cutPatch(read, held.wholeDims(), held.r0Voxels, blade, model_->mapGeometry);
    });
    cuts_.push_back(c);
    return bags;
}

void Simulation::restoreCuts(const std::vector<CutCommand>& cuts) {
    for (const CutCommand& c : cuts) {
        checkCut(c);
        editMaps(c);
        if (bondNet_) bondNet_ = std::make_shared<const BondNetwork>(breakBonds(*bondNet_, c.from, c.to, c.radius));
    }
}

void Simulation::cut(const CutCommand& c) {
    const auto t0 = PhaseClock::now();
    lastCut_ = {};
    ++cutCommands_;
    std::vector<int> bags;
    try {
        bags = editMaps(c);
    } catch (const std::domain_error&) {  // every process alike: the blade would take every bag
        lastCut_.refused = true;
        return;
    }
    lastCut_.mapSeconds = secondsSince(t0);
    const GradientMap& map = *maps_.map();
    const double h = voxelLength(map.r0Voxels);
    const bop::BladeSweep blade = sweepOf(c, h);
    std::vector<char> gone(p_.size(), 0);
    CutSums mine;
    for (std::size_t i = 0; i < p_.size(); ++i) {
        const Eigen::Vector3d x = p_.pos[i] / h;
        if (blade.holds(x)) {
            gone[i] = 1;
            mine.removed += 1;
            continue;
        }
        // A volume particle on a new face of its bag becomes the face's surface particle.
        const int s = p_.species[i];
        const std::int64_t v = map.voxelHolding(x);
        if (model_->isSurface(s) || v < 0) continue;
        const int o = map.occ[std::size_t(v)];
        if (!isSurfaceSpecies(o) || bagOfSpecies(o) != bagOfSpecies(s) || o > model_->speciesCount() ||
            !model_->isSurface(o))
            continue;
        p_.species[i] = std::uint8_t(o);
        p_.q[i] = orientationFor(map.nearestSurface(std::size_t(v)).normal.cast<double>());
        p_.normal[i] = p_.q[i] * Eigen::Vector3d::UnitZ();
        p_.omega[i].setZero();
        mine.converted += 1;
    }
    if (bondNet_) {  // a bond whose placed ends the blade passes between breaks, at both ends
        std::size_t broken = 0;
        bondNet_ = std::make_shared<const BondNetwork>(breakBonds(*bondNet_, c.from, c.to, c.radius, &broken));
        lastCut_.bondsBroken = broken;
    }
    p_.removeIf(gone);
    for (int b : bags) {
        const int s = surfaceSpeciesOfBag(b);
        if (s <= model_->speciesCount() && model_->isSurface(s)) construction_.setBirth(s, true);
    }
    const CutSums all = sumInOrder(ex_->allGather(std::vector{mine}));
    lastCut_.removed = std::size_t(all.removed);
    lastCut_.converted = std::size_t(all.converted);
    lastCut_.bags = bags.size();
    placeRegion(ex_->afterChange(p_, halo_, range_));
    forcesStale_ = true;
}

}  // namespace bop::core
