#include "DecomposedRun.hpp"

#include "DecomposedSimulation.hpp"

#include <algorithm>

namespace bop::parallel {

struct DecomposedRun::Impl {
    CartComm comm;
    DecomposedSimulation sim;
    Impl(std::shared_ptr<const core::Model> model, const core::Particles& all, DecomposedOptions options)
        : comm(MPI_COMM_WORLD, model->box), sim(comm, model, all, std::move(options)) {}
};

DecomposedRun::DecomposedRun(std::shared_ptr<const core::Model> model, const core::Particles& all,
                             DecomposedOptions options)
    : impl_(std::make_unique<Impl>(std::move(model), all, std::move(options))) {}
DecomposedRun::~DecomposedRun() = default;

void DecomposedRun::step() { impl_->sim.step(); }
void DecomposedRun::refreshForces() { impl_->sim.refreshForces(); }
void DecomposedRun::setEnergyEvery(long long n) { impl_->sim.setEnergyEvery(n); }
void DecomposedRun::setProbe(const core::ProbeState& probe) { impl_->sim.probe() = probe; }
Totals DecomposedRun::totals() const { return impl_->sim.totals(); }
core::Particles DecomposedRun::gather() const { return impl_->sim.gather(); }
void DecomposedRun::submit(const Command& command) { impl_->sim.submit(command); }
long long DecomposedRun::stepNumber() const { return impl_->sim.stepCount(); }

std::array<double, 4> DecomposedRun::agree(const std::array<double, 4>& mine) {
    std::vector<double> v(mine.begin(), mine.end());
    impl_->comm.broadcast(v);
    std::array<double, 4> out{};
    std::copy_n(v.begin(), std::min<std::size_t>(4, v.size()), out.begin());
    return out;
}

int DecomposedRun::rank() const { return impl_->comm.rank(); }
int DecomposedRun::size() const { return impl_->comm.size(); }
Coords DecomposedRun::dims() const { return impl_->comm.dims(); }

RunCounters DecomposedRun::counters() const {
    const auto& s = impl_->sim;
    const std::vector<double> all = impl_->comm.allGather(
        {double(s.haloBytesPerStep()), double(s.migrations()), double(s.rebuilds()), double(s.particles().size()),
         s.exchangeSeconds(), double(s.mapBytes())});
    RunCounters c;
    double most = 0, sum = 0;
    for (std::size_t r = 0; r < all.size(); r += 6) {
        c.exchangeSecondsMax = std::max(c.exchangeSecondsMax, all[r + 4]);
        c.mapBytesMax = std::max(c.mapBytesMax, all[r + 5]);
        c.haloBytesPerStep += all[r];
        c.migrations += all[r + 1];
        c.rebuilds = all[r + 2];
        most = std::max(most, all[r + 3]);
        sum += all[r + 3];
    }
    c.imbalance = sum > 0 ? most * double(size()) / sum : 1.0;
    c.initialImbalance = s.initialImbalance();
    c.rebalances = double(s.rebalances());
    c.births = double(s.construction().totals().births);
    c.deaths = double(s.construction().totals().deaths);
    return c;
}

}  // namespace bop::parallel
