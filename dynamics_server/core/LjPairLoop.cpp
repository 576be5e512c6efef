#include "LjPairLoop.hpp"

#include "TargetClones.hpp"

namespace bop::core {
namespace {

// Species weights of one pair: wF to each side, wE for the virial (PairKernel's tables).
struct Weights {
    const double* wF;
    const double* wE;
    std::size_t side;
    double wF11, wE11;  // pair (1, 1), copied: the force stores may alias the tables
};

// One pair: LJ force f(r)/r without branches (LjForm::forceOverR), weights per side.
template <bool OneSpecies, bool Energy>
[[gnu::always_inline]] inline void onePair(const LjForm& lj, const Weights& w, double cut2, std::size_t x,
                                           const Eigen::Vector3d& pi, std::uint32_t y, const PairInputs& in,
                                           Eigen::Vector3d& fi, PairKernel::Sums& s) {
    const Eigen::Vector3d r = in.e[y] - pi;
    const double r2 = r.squaredNorm();
    if (r2 >= cut2) return;
    ++s.inRange;
    const double fr = lj.forceOverR(r2);
    const std::size_t a = in.species[x], b = in.species[y];
    in.f[y - in.base] += ((OneSpecies ? w.wF11 : w.wF[b * w.side + a]) * fr) * r;
    fi -= ((OneSpecies ? w.wF11 : w.wF[a * w.side + b]) * fr) * r;
    const double wE = OneSpecies ? w.wE11 : w.wE[a * w.side + b];
    const double v = wE * fr * r2;
    s.virial += v;
    s.virialVolume += double(in.isVolume[a] & in.isVolume[b]) * v;  // no branch on the pair's kinds
    if constexpr (Energy) s.energy += wE * lj.energyOfR2(r2);
}

template <bool OneSpecies, bool Energy>
[[gnu::always_inline]] inline void loop(const PairKernel& kernel, const NeighbourList::Pairs& pairs,
                                        const PairInputs& in, std::size_t x0, std::size_t x1, PairKernel::Sums& sums) {
    const LjForm lj = kernel.lj();
    const double cut2 = lj.cutoff2();
    const std::size_t side = std::size_t(kernel.tableSide());
    const Weights w{kernel.ljForceWeights(), kernel.ljEnergyWeights(), side, kernel.ljForceWeights()[side + 1],
                    kernel.ljEnergyWeights()[side + 1]};
    const std::uint32_t* nbr = pairs.nbr.data();
    const std::uint32_t* start = pairs.start.data();
    PairKernel::Sums s;  // in registers, not through the reference
    for (std::size_t x = x0; x < x1; ++x) {
        const Eigen::Vector3d pi = in.e[x];  // a copy: the force stores may alias e
        Eigen::Vector3d fi = Eigen::Vector3d::Zero();
        const std::uint32_t k1 = start[x + 1];
        for (std::uint32_t k = start[x]; k < k1; ++k)
            onePair<OneSpecies, Energy>(lj, w, cut2, x, pi, nbr[k], in, fi, s);
        in.f[x - in.base] += fi;
    }
    sums.energy += s.energy;
    sums.virial += s.virial;
    sums.virialVolume += s.virialVolume;
    sums.inRange += s.inRange;
}

}  // namespace

BOP_HOT_LOOP void ljForcePairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                               bool energies, std::size_t x0, std::size_t x1, PairKernel::Sums& sums) {
    if (pairs.start.size() < 2 || x0 >= x1) return;
    const bool one = kernel.tableSide() == 2 || kernel.ljUniform();  // one set of weights for every pair
    if (one && !energies) loop<true, false>(kernel, pairs, in, x0, x1, sums);
    if (one && energies) loop<true, true>(kernel, pairs, in, x0, x1, sums);
    if (!one && !energies) loop<false, false>(kernel, pairs, in, x0, x1, sums);
    if (!one && energies) loop<false, true>(kernel, pairs, in, x0, x1, sums);
}

}  // namespace bop::core
