#include "LjPairLoop.hpp"

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
template <bool OneSpecies>
inline void onePair(const LjForm& lj, const Weights& w, double cut2, std::size_t x, const Eigen::Vector3d& pi,
                    std::uint32_t y, const Eigen::Vector3d* e, const std::uint8_t* species, const char* isVolume,
                    Eigen::Vector3d* f, Eigen::Vector3d& fi, double& virial, double& virialVolume,
                    std::size_t& inRange) {
    const Eigen::Vector3d r = e[y] - pi;
    const double r2 = r.squaredNorm();
    if (r2 >= cut2) return;
    ++inRange;
    const double fr = lj.forceOverR(r2);
    const std::size_t a = species[x], b = species[y];
    f[y] += ((OneSpecies ? w.wF11 : w.wF[b * w.side + a]) * fr) * r;
    fi -= ((OneSpecies ? w.wF11 : w.wF[a * w.side + b]) * fr) * r;
    const double v = (OneSpecies ? w.wE11 : w.wE[a * w.side + b]) * fr * r2;
    virial += v;
    if (isVolume[a] & isVolume[b]) virialVolume += v;
}

template <bool OneSpecies>
void loop(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const Eigen::Vector3d* e,
          const std::uint8_t* species, const char* isVolume, Eigen::Vector3d* f, PairKernel::Sums& sums) {
    const LjForm lj = kernel.lj();
    const double cut2 = lj.cutoff2();
    const std::size_t side = std::size_t(kernel.tableSide());
    const Weights w{kernel.ljForceWeights(), kernel.ljEnergyWeights(), side, kernel.ljForceWeights()[side + 1],
                    kernel.ljEnergyWeights()[side + 1]};
    const std::uint32_t* nbr = pairs.nbr.data();
    const std::uint32_t* start = pairs.start.data();
    double virial = 0, virialVolume = 0;
    std::size_t inRange = 0;
    const std::size_t ne = pairs.start.size() - 1;
    for (std::size_t x = 0; x < ne; ++x) {
        const Eigen::Vector3d pi = e[x];  // a copy: the force stores may alias e
        Eigen::Vector3d fi = Eigen::Vector3d::Zero();
        const std::uint32_t k1 = start[x + 1];
        for (std::uint32_t k = start[x]; k < k1; ++k)
            onePair<OneSpecies>(lj, w, cut2, x, pi, nbr[k], e, species, isVolume, f, fi, virial, virialVolume, inRange);
        f[x] += fi;
    }
    sums.virial += virial;
    sums.virialVolume += virialVolume;
    sums.inRange += inRange;
}

}  // namespace

void ljForcePairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const Eigen::Vector3d* e,
                  const std::uint8_t* species, const char* isVolume, Eigen::Vector3d* f, PairKernel::Sums& sums) {
    if (pairs.start.size() < 2) return;
    if (kernel.tableSide() == 2)
        loop<true>(kernel, pairs, e, species, isVolume, f, sums);
    else
        loop<false>(kernel, pairs, e, species, isVolume, f, sums);
}

}  // namespace bop::core
