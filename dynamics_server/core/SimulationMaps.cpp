// The gradient map(s) of a step (Simulation.hpp), the map in force (MapInForce.hpp): this region's
// windows of every keyframe, the frame in force and its blend at each step's time (Keyframes.hpp),
// and the whole maps' volumes.
#include "Simulation.hpp"

#include <cmath>
#include <limits>

namespace bop::core {

void Simulation::placeMaps() {
    if (!model_->map && !mapSource_) return;
    const bool first = maps_.frames.empty();
    if (!mapSource_ && ex_->size() == 1) {
        // One process: the model's maps themselves, the whole of each.
        if (first) maps_.frames = model_->frames.size() > 1 ? model_->frames : std::vector{model_->map};
    } else {
        if (!mapSource_) {  // windows cut from the model's maps
            GradientMap header = *model_->map;
            header.occ = {}, header.nearest = {}, header.surface = {};
            std::vector<std::shared_ptr<const GradientMap>> all = model_->frames;
            if (all.size() < 2) all = {model_->map};
            const int count = int(all.size());
            mapSource_ = MapSource{std::move(header),
                                   [all = std::move(all)](int f, const bop::VoxelWindow& w) {
                                       return bop::cropGradientMap(*all.at(std::size_t(f)), w);
                                   },
                                   count};
        }
        const GradientMap& whole = mapSource_->header;
        const double h = voxelLength(whole.r0Voxels);
        // Owned particles stray up to about half the skin out of the region between rebuilds,
        // ghosts (whose curvature weights the pair terms read) up to the list range beyond it;
        // the trilinear rule reads one voxel further.
        const double margin = 1.5 * range_ + 2 * h;
        const bop::VoxelWindow w = bop::windowAround(whole.dims(), h, maps_.region.lo, maps_.region.hi, margin);
        if (!first && w.lo == maps_.window.lo && w.hi == maps_.window.hi) return;
        maps_.window = w;
        // The force field notices a new map by its address, and holds the maps it read: a new
        // window never takes an old one's address.
        std::vector<std::shared_ptr<const GradientMap>> next;
        for (int f = 0; f < mapSource_->frames; ++f)
            next.push_back(std::make_shared<const GradientMap>(patched(std::size_t(f), mapSource_->crop(f, w))));
        maps_.frames = std::move(next);
    }
    if (!first) return;
    // The whole maps' voxel counts: each process counts the voxel centres in its region (one
    // process: all of them), summed in rank order.
    const double inf = std::numeric_limits<double>::infinity();
    const bool whole = ex_->size() == 1;
    const Eigen::Vector3d lo = whole ? Eigen::Vector3d::Constant(-inf) : maps_.region.lo;
    const Eigen::Vector3d hi = whole ? Eigen::Vector3d::Constant(inf) : maps_.region.hi;
    std::vector<MapVolume> mine;
    for (const auto& f : maps_.frames) mine.push_back(countMapVolume(*f, lo, hi));
    const std::vector<MapVolume> counts = ex_->allGather(mine);
    frameVolumes_.assign(maps_.frames.size(), {});
    for (std::size_t k = 0; k < counts.size(); ++k) {  // rank order: the same sums everywhere
        MapVolume& v = frameVolumes_[k % mine.size()];
        v.bagVoxels += counts[k].bagVoxels;
        v.volumeVoxels += counts[k].volumeVoxels;
    }
}

void Simulation::applyKeyframe(double time) {
    if (maps_.frames.empty()) return;
    const bool animated = model_->keyframes.animated() && maps_.frames.size() > 1;
    const KeyframeAt at = animated ? model_->keyframes.at(time) : KeyframeAt{};
    stats_.keyframe = maps_.at = at;
    const double h3 = std::pow(voxelLength(maps_.map()->r0Voxels), 3);
    std::vector<double> blood, cavity;
    for (const MapVolume& v : frameVolumes_) blood.push_back(v.volumeVoxels), cavity.push_back(v.bagVoxels);
    const KeyframeAt pick = frameVolumes_.size() > 1 ? at : KeyframeAt{};
    stats_.bloodVolume = blendFrames(blood, pick) * h3;
    stats_.cavityVolume = blendFrames(cavity, pick) * h3;
}

std::size_t Simulation::mapBytes() const {
    std::size_t bytes = 0;
    for (const auto& f : maps_.frames) bytes += bop::gradientMapBytes(*f);  // every keyframe's window
    return bytes;
}

}  // namespace bop::core
