#include "Simulation.hpp"

#include "SoundState.hpp"

#include <chrono>
#include <cmath>
#include <limits>

namespace bop::core {
namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }
}  // namespace

Simulation::Simulation(std::shared_ptr<const Model> model, Particles particles, Construction construction,
                       long long firstStep)
    : model_(std::move(model)), p_(std::move(particles)), construction_(std::move(construction)), drag_(*model_),
      forces_(*model_) {
    stats_.step = firstStep;
    stats_.time = double(firstStep) * model_->integration.dt;
    const Eigen::Vector3d all = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    if (model_->frames.size() > 1)
        for (const auto& f : model_->frames) frameVolumes_.push_back(countMapVolume(*f, -all, all));
    else if (model_->map)
        frameVolumes_.push_back(countMapVolume(*model_->map, -all, all));
    applyKeyframe(stats_.time);
}

void Simulation::applyKeyframe(double time) {
    const std::shared_ptr<const Model> keep = model_;  // alive while a switch replaces model_
    const Model& m = *keep;
    if (m.map) {
        const KeyframeAt at = m.keyframes.animated() && m.frames.size() > 1 ? m.keyframes.at(time) : KeyframeAt{};
        if (m.frames.size() > 1) {
            if (m.frames[std::size_t(at.a)] != m.map) {
                auto next = std::make_shared<Model>(m);  // weights and species stay; the map moves on
                next->map = m.frames[std::size_t(at.a)];
                model_ = std::move(next);  // the forces of this step's new positions are the new map's
            }
            forces_.setMapBlend(model_->frames[std::size_t(at.b)].get(), at.w);
        }
        stats_.keyframe = at;
        const double h3 = std::pow(kR0 / m.map->r0Voxels, 3);
        std::vector<double> blood, cavity;
        for (const MapVolume& v : frameVolumes_) blood.push_back(v.volumeVoxels), cavity.push_back(v.bagVoxels);
        const KeyframeAt pick = frameVolumes_.size() > 1 ? at : KeyframeAt{};
        stats_.bloodVolume = blendFrames(blood, pick) * h3;
        stats_.cavityVolume = blendFrames(cavity, pick) * h3;
    }
}

void Simulation::setModel(std::shared_ptr<const Model> m) {
    model_ = std::move(m);
    drag_ = DragFactors(*model_);
    forces_ = ForceField(*model_);
    forcesValid_ = false;
}

void Simulation::refreshForces() {
    forces_.compute(*model_, probe_, p_, stats_.forces, &times_.forces);
    forcesValid_ = true;
}

void Simulation::step() {
    auto t0 = Clock::now();
    applyKeyframe(double(stats_.step + 1) * model_->integration.dt);  // the time of this step's forces
    const std::size_t before = p_.size();
    stats_.built = construction_.update(*model_, p_, stats_.step);
    if (p_.size() != before || stats_.built.deaths) forcesValid_ = false;
    times_.construction += since(t0);
    if (!forcesValid_) refreshForces();

    t0 = Clock::now();
    kickDrift(*model_, drag_, p_);
    times_.integrate += since(t0);
    forces_.compute(*model_, probe_, p_, stats_.forces, &times_.forces, (stats_.step + 1) % energyEvery_ == 0);
    t0 = Clock::now();
    stats_.kinetic = kick(*model_, drag_, p_);
    stats_.blood = bloodSums(*model_, p_);
    times_.integrate += since(t0);
    ++stats_.step;
    stats_.time += model_->integration.dt;
    if (!sound(*model_, p_, stats_.forces.probeReaction))
        throw UnsoundState(stats_.step, unsoundness(*model_, p_, stats_.forces.probeReaction));
}

}  // namespace bop::core
