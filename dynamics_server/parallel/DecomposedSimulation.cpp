#include "DecomposedSimulation.hpp"

namespace bop::parallel {

DecomposedSimulation::DecomposedSimulation(const CartComm& comm, std::shared_ptr<const core::Model> model,
                                           const core::Particles& all, DecomposedOptions options)
    : exchange_(comm, model->box, core::haloReach(*model, options)),
      sim_(std::move(model), all, std::move(options), exchange_) {}

}  // namespace bop::parallel
