#include "Simulation.hpp"

#include <chrono>

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
    times_.integrate += since(t0);
    ++stats_.step;
    stats_.time += model_->integration.dt;
}

}  // namespace bop::core
