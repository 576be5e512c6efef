#include "Construction.hpp"

#include "ConstructionSteps.hpp"
#include "Integrator.hpp"

#include <algorithm>
#include <stdexcept>

namespace bop::core {
namespace {

std::uint64_t splitMix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

bool everywhere(const Eigen::Vector3d&) {
    return true;
}

}  // namespace

std::uint64_t mixHash(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
    return splitMix(splitMix(splitMix(splitMix(a) ^ b) ^ c) ^ d);
}

Construction::Construction(ConstructionParams params, std::vector<ConstructionEvent> timeline, int speciesCount)
    : params_(params), timeline_(std::move(timeline)), birth_(std::size_t(speciesCount) + 1, 0) {
    std::stable_sort(timeline_.begin(), timeline_.end(),
                     [](const ConstructionEvent& a, const ConstructionEvent& b) { return a.step < b.step; });
}

void Construction::setBirth(int species, bool on) {
    if (species < 1 || std::size_t(species) >= birth_.size()) throw std::out_of_range("no such species");
    birth_[std::size_t(species)] = on;
}

void Construction::restore(const std::vector<char>& births, std::uint64_t seeds, std::uint64_t nextId) {
    if (births.size() + 1 != birth_.size())
        throw std::invalid_argument("checkpoint has birth switches for " + std::to_string(births.size()) +
                                    " species, the scene has " + std::to_string(birth_.size() - 1));
    std::copy(births.begin(), births.end(), birth_.begin() + 1);
    seeds_ = seeds;
    nextId_ = std::max(nextId_, nextId);
}

bool Construction::building() const {
    return std::find(birth_.begin(), birth_.end(), char(1)) != birth_.end();
}

bool Construction::checkDue(long long step) const {
    return params_.everySteps > 0 && step % params_.everySteps == 0 && building();
}

std::vector<ConstructionEvent> Construction::eventsAt(long long step) const {
    std::vector<ConstructionEvent> out;
    for (const auto& e : timeline_)
        if (e.step == step) out.push_back(e);
    return out;
}

Eigen::Vector3d Construction::defaultSeedPosition(const Model& model, const GradientMap* map, int species) const {
    if (!map) throw std::invalid_argument("seeding needs a gradient map");
    const auto best = defaultSeed(params_, model, *map, species, everywhere);
    if (!best) throw std::invalid_argument("species " + std::to_string(species) + " has no voxels in the map");
    return best->pos;
}

std::uint64_t Construction::seed(const Model& model, const GradientMap* map, Particles& p, int species,
                                 const Eigen::Vector3d& position, bool add) {
    const std::uint64_t gid = takeIds(1);
    ++seeds_;
    if (!add) return gid;
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    if (map) {
        const GradientMap& m = *map;
        n = m.nearestSurface(m.voxelAt((position / voxelLength(m.r0Voxels)).array().floor().cast<int>().matrix()))
                .normal.cast<double>();
    }
    p.add(position, species, gid, model.isSurface(species) ? orientationFor(n) : Eigen::Quaterniond::Identity());
    return gid;
}

}  // namespace bop::core
