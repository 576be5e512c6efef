// The gradient map(s) of a step (Simulation.hpp): this region's windows of every keyframe, the
// frame in force and its blend at each step's time (Keyframes.hpp), and the whole maps' volumes.
#include "Simulation.hpp"

#include <cmath>
#include <limits>

namespace bop::core {

void Simulation::placeMaps() {
    if (!model_->map && !mapSource_) return;
    const bool first = frames_.empty();
    if (!mapSource_ && ex_->size() == 1) {
        // One process: the model's maps themselves, the whole of each.
        if (first) frames_ = model_->frames.size() > 1 ? model_->frames : std::vector{model_->map};
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
        const bop::VoxelWindow w = bop::windowAround(whole.dims(), h, region_.lo, region_.hi, margin);
        if (!first && w.lo == window_.lo && w.hi == window_.hi) return;
        window_ = w;
        // The new windows are made while the old ones live, so the force field, which notices a
        // new map by its address, cannot mistake one for the other.
        std::vector<std::shared_ptr<const GradientMap>> next;
        for (int f = 0; f < mapSource_->frames; ++f)
            next.push_back(std::make_shared<const GradientMap>(mapSource_->crop(f, w)));
        frames_ = std::move(next);
    }
    field_.setMapBlend(frames_[std::size_t(stats_.keyframe.b)].get(), stats_.keyframe.w);  // not the old window's
    if (!first) return;
    // The whole maps' voxel counts: each process counts the voxel centres in its region (one
    // process: all of them), summed in rank order.
    const double inf = std::numeric_limits<double>::infinity();
    const bool whole = ex_->size() == 1;
    const Eigen::Vector3d lo = whole ? Eigen::Vector3d::Constant(-inf) : region_.lo;
    const Eigen::Vector3d hi = whole ? Eigen::Vector3d::Constant(inf) : region_.hi;
    std::vector<MapVolume> mine;
    for (const auto& f : frames_) mine.push_back(countMapVolume(*f, lo, hi));
    const std::vector<MapVolume> counts = ex_->allGather(mine);
    frameVolumes_.assign(frames_.size(), {});
    for (std::size_t k = 0; k < counts.size(); ++k) {  // rank order: the same sums everywhere
        MapVolume& v = frameVolumes_[k % mine.size()];
        v.bagVoxels += counts[k].bagVoxels;
        v.volumeVoxels += counts[k].volumeVoxels;
    }
}

void Simulation::placeLocal() {
    auto local = std::make_shared<Model>(*model_);
    local->box = region_;
    if (!frames_.empty()) {
        local->map = frames_[std::size_t(stats_.keyframe.a)];
        local->frames = frames_.size() > 1 ? frames_ : std::vector<std::shared_ptr<const GradientMap>>{};
    }
    local_ = std::move(local);
}

void Simulation::applyKeyframe(double time) {
    if (frames_.empty()) return;
    const bool animated = model_->keyframes.animated() && frames_.size() > 1;
    const KeyframeAt at = animated ? model_->keyframes.at(time) : KeyframeAt{};
    stats_.keyframe = at;
    if (local_->map != frames_[std::size_t(at.a)]) placeLocal();
    field_.setMapBlend(frames_[std::size_t(at.b)].get(), at.w);
    const double h3 = std::pow(voxelLength(local_->map->r0Voxels), 3);
    std::vector<double> blood, cavity;
    for (const MapVolume& v : frameVolumes_) blood.push_back(v.volumeVoxels), cavity.push_back(v.bagVoxels);
    const KeyframeAt pick = frameVolumes_.size() > 1 ? at : KeyframeAt{};
    stats_.bloodVolume = blendFrames(blood, pick) * h3;
    stats_.cavityVolume = blendFrames(cavity, pick) * h3;
}

std::size_t Simulation::mapBytes() const {
    std::size_t bytes = 0;
    for (const auto& f : frames_) bytes += bop::gradientMapBytes(*f);  // every keyframe's window
    return bytes;
}

}  // namespace bop::core
