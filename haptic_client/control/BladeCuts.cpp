#include "control/BladeCuts.hpp"

#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapEdit.hpp"
#include "bop/common/Units.hpp"

#include <chrono>

namespace bop::haptic {

std::optional<Stroke> BladePath::tick(double tS, bool cutting, const Eigen::Vector3d& x) {
    if (!cutting) {
        last_.reset();
        return std::nullopt;
    }
    if (!last_) {  // a press: the path starts with a point blade where the blade is
        last_ = x;
        lastS_ = tS;
        return Stroke{x, x, radius_};
    }
    if ((x - *last_).norm() < radius_ || tS - lastS_ < minIntervalS_) return std::nullopt;
    const Stroke s{*last_, x, radius_};
    last_ = x;
    lastS_ = tS;
    return s;
}

FieldCutter::FieldCutter(FieldForce& field, SurfaceGeometryParams geometry)
    : field_(field), geometry_(geometry), worker_([this] { work(); }) {}

FieldCutter::~FieldCutter() {
    {
        std::lock_guard lock(m_);
        stop_ = true;
    }
    wake_.notify_one();
    worker_.join();
}

void FieldCutter::push(const Stroke& s) {
    push(CopyEdit{s, {}});
}

void FieldCutter::push(CopyEdit e) {
    {
        std::lock_guard lock(m_);
        queue_.push_back(std::move(e));
    }
    wake_.notify_one();
}

void FieldCutter::drain() {
    std::unique_lock lock(m_);
    done_.wait(lock, [&] { return queue_.empty() && !busy_; });
}

std::size_t FieldCutter::applied() const {
    std::lock_guard lock(m_);
    return applied_;
}

std::size_t FieldCutter::refused() const {
    std::lock_guard lock(m_);
    return refused_;
}

std::string FieldCutter::lastRefusal() const {
    std::lock_guard lock(m_);
    return lastRefusal_;
}

double FieldCutter::slowestMs() const {
    std::lock_guard lock(m_);
    return slowestMs_;
}

void FieldCutter::apply(const CopyEdit& e) {
    const std::shared_ptr<const GradientMap> map = field_.map();
    const MapWindowReader read = [&](const VoxelWindow& w) { return cropGradientMap(*map, w); };
    MapPatch patch;
    try {
        if (e.stroke.radius > 0) {
            const double h = voxelLength(map->r0Voxels);
            BladeSweep blade;
            blade.a = e.stroke.from / h;
            blade.b = e.stroke.to / h;
            blade.radius = e.stroke.radius / h;
            patch = cutPatch(read, map->wholeDims(), map->r0Voxels, blade, geometry_);
        } else {
            patch = voxelsPatch(read, map->wholeDims(), map->r0Voxels, e.voxels, geometry_);
        }
    } catch (const std::exception& x) {  // would take every bag, or voxels beyond the grid: the map stays
        std::lock_guard lock(m_);
        ++refused_;
        lastRefusal_ = x.what();
        return;
    }
    if (!patch.empty()) field_.setMap(std::make_shared<const GradientMap>(applyPatch(*map, patch)));
}

void FieldCutter::work() {
    for (;;) {
        CopyEdit e;
        {
            std::unique_lock lock(m_);
            wake_.wait(lock, [&] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return;  // stopping, nothing left
            e = std::move(queue_.front());
            queue_.pop_front();
            busy_ = true;
        }
        const auto t0 = std::chrono::steady_clock::now();
        apply(e);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        {
            std::lock_guard lock(m_);
            ++applied_;
            slowestMs_ = std::max(slowestMs_, ms);
            busy_ = false;
        }
        done_.notify_all();
    }
}

}  // namespace bop::haptic
