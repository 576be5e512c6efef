#include "ClusterForm.hpp"

#include "ClusterLjLoop.hpp"
#include "core/LjPairLoop.hpp"
#include "core/PrunedPairs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace bop::tools {
namespace {

// Seconds of one run of pass().
template <class Pass>
double timed(Pass pass) {
    const auto t0 = std::chrono::steady_clock::now();
    pass();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double relative(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(b), 1e-300);
}

}  // namespace

ClusterFormResult measureClusterForm(const core::Model& model, const core::Params& params,
                                     const core::Particles& particles, const core::Box& box, int repeats) {
    const core::PairKernel kernel(model, params, false);
    const double cutoff = kernel.lj().cutoff();
    core::NeighbourList list;
    list.build(box, cutoff + model.integration.skinR0 * kR0, particles.pos, {}, nullptr, &particles.id, cutoff);
    core::PrunedPairs pruned;
    pruned.prune(list, cutoff + 0.05 * kR0, cutoff + 0.05 * kR0, 0.025 * kR0);
    const core::NeighbourList::Pairs& pairs = *pruned.sets().lj;
    const std::size_t ne = list.entryCount();
    std::vector<std::uint8_t> species(ne);
    std::vector<char> isVolume(std::size_t(model.speciesCount()) + 1, 0), entryVolume(ne);
    for (int s = 1; s <= model.speciesCount(); ++s) isVolume[std::size_t(s)] = !model.isSurface(s);
    for (std::size_t k = 0; k < ne; ++k) {
        species[k] = particles.species[list.owner()[k]];
        entryVolume[k] = isVolume[species[k]];
    }
    ClusterPairs clusters;
    clusters.build(pairs, ne, entryVolume);
    clusters.setPositions(list.positions().data());

    ClusterFormResult out;
    out.clusterPairs = clusters.pairCount();
    std::vector<Eigen::Vector3d> rowsForce(ne), mixedForce(ne);
    core::PairKernel::Sums rows, mixed, cl;
    const auto rowsPass = [&](bool mix, std::vector<Eigen::Vector3d>& f, core::PairKernel::Sums& s, bool energies) {
        std::fill(f.begin(), f.end(), Eigen::Vector3d::Zero());
        s = {};
        const core::PairInputs in{list.positions().data(), species.data(), isVolume.data(), f.data(), 0, mix};
        core::ljForcePairs(kernel, pairs, in, energies, 0, ne, s);
    };
    std::vector<double> clusterForce(12 * clusters.clusterCount());
    const auto clusterPass = [&](bool energies) {
        std::fill(clusterForce.begin(), clusterForce.end(), 0.0);
        cl = {};
        ljClusterPairs(kernel, clusters, species.data(), clusterForce.data(), energies, 0, clusters.clusterCount(), cl);
    };
    // Forces alone, as most steps; alternating, so that a busy neighbour on the machine slows each alike.
    double tRows = 1e30, tMixed = 1e30, tClusters = 1e30;
    for (int r = 0; r < repeats; ++r) {
        tRows = std::min(tRows, timed([&] { rowsPass(false, rowsForce, rows, false); }));
        tMixed = std::min(tMixed, timed([&] { rowsPass(true, mixedForce, mixed, false); }));
        tClusters = std::min(tClusters, timed([&] { clusterPass(false); }));
    }
    rowsPass(false, rowsForce, rows, true);  // then once more with energies, for the checks
    rowsPass(true, mixedForce, mixed, true);
    clusterPass(true);
    out.inRange = rows.inRange;
    out.sameCount = cl.inRange == rows.inRange && mixed.inRange == rows.inRange;
    const double perPair = 1e9 / double(std::max<std::size_t>(rows.inRange, 1));
    out.rowsDoubleNs = tRows * perPair, out.rowsMixedNs = tMixed * perPair, out.clusterNs = tClusters * perPair;
    double d2 = 0, f2 = 0;
    for (std::size_t k = 0; k < ne; ++k) {
        const std::size_t c = k / ClusterPairs::kSize, a = k % ClusterPairs::kSize;
        const Eigen::Vector3d fc(clusterForce[12 * c + a], clusterForce[12 * c + 4 + a], clusterForce[12 * c + 8 + a]);
        d2 += (fc - rowsForce[k]).squaredNorm();
        f2 += rowsForce[k].squaredNorm();
    }
    out.forceDifference = std::sqrt(d2 / std::max(f2, 1e-300));
    out.virialDifference = std::max(relative(cl.virial, rows.virial), relative(cl.virialVolume, rows.virialVolume));
    out.energyDifference = relative(cl.energy, rows.energy);
    return out;
}

}  // namespace bop::tools
