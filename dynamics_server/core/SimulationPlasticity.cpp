// Lasting deformation in a step (Plasticity.hpp, docs/physics.md §9.4): the empty voxels every
// process finds in its region, gathered in voxel order and timed alike everywhere; those that
// yield leave their bags.
#include "Simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop::core {
namespace {

// Particles here and the ghosts, binned in cubes of r0 over this process's map window.
class Bins {
public:
    Bins(const GradientMap& map, const Particles& p, const Halo& halo, double h)
        : lo_(map.origin.cast<double>() * h),
          n_(Eigen::Vector3d(map.dims().nx, map.dims().ny, map.dims().nz) * h / kR0),
          cells_(std::size_t(n_.x() + 1) * std::size_t(n_.y() + 1) * std::size_t(n_.z() + 1)) {
        for (const Eigen::Vector3d& x : p.pos) add(x);
        for (const Eigen::Vector3d& x : halo.pos) add(x);
    }
    // Whether a particle lies in the cylinder of radius `radius` along n from `behind` behind c to
    // `ahead` in front of it.
    bool anyInCylinder(const Eigen::Vector3d& c, const Eigen::Vector3d& n, double behind, double ahead,
                       double radius) const {
        const Eigen::Vector3i k = cell(c);
        const int reach = int(std::ceil(std::max(ahead, behind) / kR0)) + 1;
        for (int dz = -reach; dz <= reach; ++dz)
            for (int dy = -reach; dy <= reach; ++dy)
                for (int dx = -reach; dx <= reach; ++dx) {
                    const Eigen::Vector3i u = k + Eigen::Vector3i(dx, dy, dz);
                    if ((u.array() < 0).any() || u.x() > int(n_.x()) || u.y() > int(n_.y()) || u.z() > int(n_.z()))
                        continue;
                    for (const Eigen::Vector3d& x : cells_[index(u)]) {
                        const Eigen::Vector3d r = x - c;
                        const double a = r.dot(n);
                        if (a >= -behind && a <= ahead && r.squaredNorm() - a * a <= radius * radius) return true;
                    }
                }
        return false;
    }

private:
    Eigen::Vector3i cell(const Eigen::Vector3d& x) const {
        const Eigen::Vector3d k = ((x - lo_) / kR0).cwiseMax(0.0).cwiseMin(n_);
        return k.cast<int>();
    }
    std::size_t index(const Eigen::Vector3i& u) const {
        return std::size_t(u.x()) +
               std::size_t(n_.x() + 1) * (std::size_t(u.y()) + std::size_t(n_.y() + 1) * std::size_t(u.z()));
    }
    void add(const Eigen::Vector3d& x) { cells_[index(cell(x))].push_back(x); }
    Eigen::Vector3d lo_, n_;
    std::vector<std::vector<Eigen::Vector3d>> cells_;
};

}  // namespace

void Simulation::checkDents() {
    const PlasticityParams& pl = model_->plasticity;
    if (!pl.on || !maps_.map() || stats_.step % std::max(1LL, pl.everySteps) != 0) return;
    const GradientMap& map = *maps_.map();
    const double h = voxelLength(map.r0Voxels);
    const Bins bins(map, p_, halo_, h);
    const double band = pl.bandR0 * map.r0Voxels, deep = pl.yieldDepthR0 * map.r0Voxels;  // voxels
    std::vector<std::uint64_t> mine, mineDeep;
    for (std::size_t v = 0; v < map.occ.size(); ++v) {
        if (map.occ[v] == 0) continue;
        const double depth = map.delta(v).cast<double>().norm();
        if (depth > band) continue;
        const Eigen::Vector3d centre = (map.wholeCoords(v).cast<double>() + Eigen::Vector3d::Constant(0.5)) * h;
        if (!ex_->owns(centre)) continue;  // another process's region: it finds this one
        // In front of every particle: none in the cylinder looking out along the surface's normal.
        const Eigen::Vector3d n = map.nearestSurface(v).normal.cast<double>();
        if (bins.anyInCylinder(centre, n, kBehindR0 * kR0, kAheadR0 * kR0, kAcrossR0 * kR0)) continue;
        mine.push_back(map.wholeIndex(v));
        if (deep > 0 && depth >= deep) mineDeep.push_back(map.wholeIndex(v));
    }
    std::vector<std::uint64_t> empty = ex_->allGatherV(mine), deepEmpty = ex_->allGatherV(mineDeep);
    std::sort(empty.begin(), empty.end());
    std::sort(deepEmpty.begin(), deepEmpty.end());
    std::map<std::uint64_t, long long> still;
    std::vector<std::uint64_t> yielded;
    const long long holdSteps = pl.holdTime > 0 ? std::llround(pl.holdTime / model_->integration.dt) : -1;
    for (std::uint64_t v : empty) {
        const auto was = dentedSince_.find(v);
        // A dent is a change: a voxel in front since the first look (a sharp edge the sheet rounds
        // off) is the bag at rest, never a dent.
        const bool fresh = frontSeen_ && !std::binary_search(frontBefore_.begin(), frontBefore_.end(), v);
        if (was == dentedSince_.end() && !fresh) continue;
        const long long since = was == dentedSince_.end() ? stats_.step : was->second;
        if ((holdSteps >= 0 && stats_.step - since >= holdSteps) ||
            std::binary_search(deepEmpty.begin(), deepEmpty.end(), v))
            yielded.push_back(v);
        else
            still.emplace(v, since);  // a voxel a particle comes back to starts again
    }
    dentedSince_ = std::move(still);
    frontBefore_ = std::move(empty);
    frontSeen_ = true;
    if (yielded.empty()) return;
    yieldVoxels(yielded);
    yields_.push_back(std::move(yielded));
    forcesStale_ = true;
}

void Simulation::yieldVoxels(const std::vector<std::uint64_t>& voxels) {
    patchMaps([&](const bop::MapWindowReader& read, const GradientMap& held) {
        return bop::voxelsPatch(read, held.wholeDims(), held.r0Voxels, voxels, model_->mapGeometry);
    });
}

void Simulation::restoreYields(const std::vector<std::vector<std::uint64_t>>& yields) {
    if (!yields.empty() && !maps_.map()) throw std::invalid_argument("yields: the run has no gradient map");
    for (const auto& y : yields) {
        if (!std::is_sorted(y.begin(), y.end())) throw std::invalid_argument("yields: voxels out of order");
        yieldVoxels(y);
        yields_.push_back(y);
    }
}

}  // namespace bop::core
