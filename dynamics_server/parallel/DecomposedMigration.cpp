// Particles to the rank that owns their position, and the cut planes that balance the ranks
// (see DecomposedSimulation.hpp).
#include "DecomposedSimulation.hpp"

#include "Packing.hpp"

#include <algorithm>
#include <cmath>

namespace bop::parallel {

double DecomposedSimulation::imbalanceNow() const {
    return Decomposition::imbalance(comm_.allGather({double(p_.size())}));
}

void DecomposedSimulation::migrateHome() {
    // One hop per axis per pass; moved planes, or a particle faster than half the skin per step,
    // can put a particle several subdomains away.
    const int passes = std::max({comm_.dims()[0], comm_.dims()[1], comm_.dims()[2]});
    for (int pass = 0; pass < passes; ++pass) {
        wrapAndMigrate();
        bool here = true;
        for (const auto& x : p_.pos) here = here && dec_.owner(x) == comm_.coords();
        if (comm_.allTrue(here)) return;
    }
}

void DecomposedSimulation::rebalance() {
    constexpr int kBins = 256;
    const core::Box& box = model_->box;
    const Eigen::Vector3d L = box.size();
    std::vector<double> local(3 * kBins, 0.0);
    for (const auto& x : p_.pos)
        for (int a = 0; a < 3; ++a) {
            double u = x[a];
            if (box.periodic[std::size_t(a)]) u -= L[a] * std::floor((u - box.lo[a]) / L[a]);
            const int b = std::clamp(int((u - box.lo[a]) / L[a] * kBins), 0, kBins - 1);
            local[std::size_t(a * kBins + b)] += 1;
        }
    const std::vector<double> all = comm_.allGather(local);  // whole counts: exact in any order
    std::array<std::vector<double>, 3> histogram;
    for (int a = 0; a < 3; ++a) {
        histogram[std::size_t(a)].assign(kBins, 0.0);
        for (std::size_t r = 0; r < std::size_t(comm_.size()); ++r)
            for (int b = 0; b < kBins; ++b) histogram[std::size_t(a)][std::size_t(b)] += all[r * local.size() + std::size_t(a * kBins + b)];
    }
    dec_.balance(histogram);
    sub_.box = dec_.subdomain(comm_.coords());
    cropMap();
    migrateHome();
    buildHalo(range_);
    field_.requestRebuild();
    ++rebalances_;
}

void DecomposedSimulation::wrapAndMigrate() {
    const core::Box& box = model_->box;
    const Eigen::Vector3d L = box.size();
    for (auto& x : p_.pos)
        for (int a = 0; a < 3; ++a)
            if (box.periodic[std::size_t(a)] && (x[a] < box.lo[a] || x[a] >= box.hi[a])) {
                x[a] -= L[a] * std::floor((x[a] - box.lo[a]) / L[a]);
                if (x[a] >= box.hi[a]) x[a] = box.lo[a];  // -1e-17 + L rounds to L: that is lo
            }
    for (int a = 0; a < 3; ++a) {
        if (comm_.dims()[std::size_t(a)] == 1) continue;
        std::vector<double> toLower, toUpper, fromUpper, fromLower;
        std::vector<char> leaves(p_.size(), 0);
        for (std::size_t i = 0; i < p_.size(); ++i) {
            const int c = dec_.owner(p_.pos[i])[std::size_t(a)], mine = comm_.coords()[std::size_t(a)];
            if (c == mine) continue;
            // One hop towards the owner (migrateHome() repeats while any particle is away); across
            // a periodic seam the owner's coordinate wraps, so there the nearer way round decides.
            const int n = comm_.dims()[std::size_t(a)];
            const int down = ((mine - c) % n + n) % n, up = ((c - mine) % n + n) % n;
            const bool lower = box.periodic[std::size_t(a)] ? down <= up : c < mine;
            if ((lower ? comm_.lower(a) : comm_.upper(a)) == MPI_PROC_NULL) continue;  // past an open face: stays
            packParticle(p_, i, lower ? toLower : toUpper);
            leaves[i] = 1;
            ++migrations_;
        }
        comm_.sendRecv(toLower, comm_.lower(a), fromUpper, comm_.upper(a), 100 + 4 * a);
        comm_.sendRecv(toUpper, comm_.upper(a), fromLower, comm_.lower(a), 102 + 4 * a);
        p_.removeIf(leaves);
        unpackParticles(fromUpper, p_);
        unpackParticles(fromLower, p_);
    }
}

}  // namespace bop::parallel
