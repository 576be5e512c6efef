// The ranks of a decomposed run behind core::Exchange: commands, balance and migration (the
// halo plan is MpiHalo.cpp). See MpiExchange.hpp.
#include "MpiExchange.hpp"

#include "Commands.hpp"

#include <algorithm>
#include <cmath>

namespace bop::parallel {

MpiExchange::MpiExchange(const CartComm& comm, const core::Box& box, double reach)
    : comm_(comm), box_(box), dec_(box, comm.dims(), reach) {}

void MpiExchange::broadcast(std::vector<core::Command>& commands) {
    std::vector<CommandRecord> records;  // rank 0's queue
    if (comm_.rank() == 0)
        for (const core::Command& c : commands) records.push_back(recordOf(c));
    comm_.broadcast(records);
    if (comm_.rank() != 0) {
        commands.clear();
        for (const CommandRecord& r : records) commands.push_back(commandOf(r));
    }
}

double MpiExchange::imbalance(std::size_t mine) {
    return Decomposition::imbalance(comm_.allGather(std::vector<double>{double(mine)}));
}

void MpiExchange::migrate(core::Particles& p) {
    // One hop per axis per pass; moved planes, or a particle faster than half the skin per step,
    // can put a particle several subdomains away.
    const int passes = std::max({comm_.dims()[0], comm_.dims()[1], comm_.dims()[2]});
    for (int pass = 0; pass < passes; ++pass) {
        wrapAndMigrate(p);
        bool here = true;
        for (const auto& x : p.pos) here = here && dec_.owner(x) == comm_.coords();
        if (comm_.allTrue(here)) return;
    }
}

bool MpiExchange::rebalance(core::Particles& p) {
    if (initialImbalance_ < 0) initialImbalance_ = imbalance(p.size());  // uniform cuts, before the first balancing
    constexpr int kBins = 256;
    const Eigen::Vector3d L = box_.size();
    std::vector<double> local(3 * kBins, 0.0);
    for (const auto& x : p.pos)
        for (int a = 0; a < 3; ++a) {
            double u = x[a];
            if (box_.periodic[std::size_t(a)]) u -= L[a] * std::floor((u - box_.lo[a]) / L[a]);
            const int b = std::clamp(int((u - box_.lo[a]) / L[a] * kBins), 0, kBins - 1);
            local[std::size_t(a * kBins + b)] += 1;
        }
    const std::vector<double> all = comm_.allGather(local);  // whole counts: exact in any order
    std::array<std::vector<double>, 3> histogram;
    for (int a = 0; a < 3; ++a) {
        histogram[std::size_t(a)].assign(kBins, 0.0);
        for (std::size_t r = 0; r < std::size_t(comm_.size()); ++r)
            for (int b = 0; b < kBins; ++b)
                histogram[std::size_t(a)][std::size_t(b)] += all[r * local.size() + std::size_t(a * kBins + b)];
    }
    dec_.balance(histogram);
    migrate(p);
    ++rebalances_;
    return true;
}

void MpiExchange::wrapAndMigrate(core::Particles& p) {
    for (auto& x : p.pos) x = box_.wrap(x);  // outside the periodic box: its image inside
    for (int a = 0; a < 3; ++a) {
        if (comm_.dims()[std::size_t(a)] == 1) continue;
        std::vector<core::ParticleRecord> toLower, toUpper, fromUpper, fromLower;
        std::vector<char> leaves(p.size(), 0);
        for (std::size_t i = 0; i < p.size(); ++i) {
            const int c = dec_.owner(p.pos[i])[std::size_t(a)], mine = comm_.coords()[std::size_t(a)];
            if (c == mine) continue;
            // One hop towards the owner (migrate() repeats while any particle is away); across a
            // periodic seam the owner's coordinate wraps, so there the nearer way round decides.
            const int n = comm_.dims()[std::size_t(a)];
            const int down = ((mine - c) % n + n) % n, up = ((c - mine) % n + n) % n;
            const bool lower = box_.periodic[std::size_t(a)] ? down <= up : c < mine;
            if ((lower ? comm_.lower(a) : comm_.upper(a)) == MPI_PROC_NULL) continue;  // past an open face: stays
            (lower ? toLower : toUpper).push_back(core::ParticleRecord::of(p, i));
            leaves[i] = 1;
            ++migrations_;
        }
        comm_.sendRecv(toLower, comm_.lower(a), fromUpper, comm_.upper(a), tag(MigrationTag::ToLower, a));
        comm_.sendRecv(toUpper, comm_.upper(a), fromLower, comm_.lower(a), tag(MigrationTag::ToUpper, a));
        p.removeIf(leaves);
        for (const auto& r : fromUpper) r.appendTo(p);
        for (const auto& r : fromLower) r.appendTo(p);
    }
}

}  // namespace bop::parallel
