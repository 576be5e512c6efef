#pragma once
// A core::Run over this job's ranks (parallel::rankExchanges), as bop-server makes one under mpirun.
#include "core/Run.hpp"
#include "parallel/RankExchanges.hpp"

namespace bop::testing {

struct RankRun : core::Run {
    RankRun(std::shared_ptr<const core::Model> model, const core::Particles& all, core::SimulationOptions options = {})
        : core::Run(std::move(model), all, std::move(options), parallel::rankExchanges()) {}
};

}  // namespace bop::testing
