#include "LjPairLoop.hpp"

#include "TargetClones.hpp"

#include <algorithm>
#include <cmath>

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

// ---- mixed precision ----

constexpr std::uint32_t kLanes = 16;  // one AVX-512 register of floats; two AVX2, four SSE2

// LjForm::forceOverR's constants rounded to float.
struct Lj32 {
    float cut2, fShift, rOn, invWidth;
    explicit Lj32(const LjForm& lj)
        : cut2(float(lj.cutoff2())),
          fShift(float(lj.forceShift())),
          rOn(float(lj.switchOn())),
          invWidth(float(lj.invSwitchWidth())) {}
};

template <bool OneSpecies, bool Energy>
[[gnu::always_inline]] inline void loopMixed(const PairKernel& kernel, const NeighbourList::Pairs& pairs,
                                             const PairInputs& in, std::size_t x0, std::size_t x1,
                                             PairKernel::Sums& sums) {
    const LjForm lj = kernel.lj();
    const Lj32 c(lj);
    const std::size_t side = std::size_t(kernel.tableSide());
    const float* wF = kernel.ljForceWeights32();
    const float* wE = kernel.ljEnergyWeights32();
    const float wF11 = wF[side + 1], wE11 = wE[side + 1];
    const double wE11d = kernel.ljEnergyWeights()[side + 1];
    const std::uint32_t* nbr = pairs.nbr.data();
    const std::uint32_t* start = pairs.start.data();
    PairKernel::Sums s;
    alignas(64) float dx[kLanes], dy[kLanes], dz[kLanes], fr[kLanes], r2s[kLanes];
    for (std::size_t x = x0; x < x1; ++x) {
        const Eigen::Vector3d pi = in.e[x];  // a copy: the force stores may alias e
        const std::size_t a = in.species[x];
        Eigen::Vector3d fi = Eigen::Vector3d::Zero();
        const std::uint32_t k1 = start[x + 1];
        for (std::uint32_t k = start[x]; k < k1; k += kLanes) {
            const std::uint32_t n = std::min(kLanes, k1 - k);
            const std::uint32_t* y = nbr + k;
            for (std::uint32_t l = 0; l < kLanes; ++l) {  // lanes past n repeat the row's last entry
                const Eigen::Vector3d& q = in.e[y[l < n ? l : n - 1]];
                dx[l] = float(q.x() - pi.x());
                dy[l] = float(q.y() - pi.y());
                dz[l] = float(q.z() - pi.z());
            }
            for (std::uint32_t l = 0; l < kLanes; ++l) {  // LjForm::forceOverR in float, 0 beyond the cutoff
                const float r2 = dx[l] * dx[l] + dy[l] * dy[l] + dz[l] * dz[l];
                const bool inside = r2 < c.cut2 && l < n;
                const float q2 = inside ? r2 : 1.0f;
                const float inv2 = 1.0f / q2;
                const float r = std::sqrt(q2);
                const float f = (4.5f * inv2 - 1.5f) * inv2 - c.fShift;
                const float u = (r - c.rOn) * c.invWidth;
                const float t = 0.5f * (u + std::abs(u));
                fr[l] = inside ? f * (1.0f + t * t * (2.0f * t - 3.0f)) * (r * inv2) : 0.0f;
                r2s[l] = inside ? r2 : 0.0f;
            }
            for (std::uint32_t l = 0; l < n; ++l) {  // in list order, into the double sums
                const std::uint32_t j = y[l];
                const std::size_t b = in.species[j];
                const float toJ = (OneSpecies ? wF11 : wF[b * side + a]) * fr[l];
                const float toI = (OneSpecies ? wF11 : wF[a * side + b]) * fr[l];
                in.f[j - in.base] += Eigen::Vector3d(double(toJ * dx[l]), double(toJ * dy[l]), double(toJ * dz[l]));
                fi -= Eigen::Vector3d(double(toI * dx[l]), double(toI * dy[l]), double(toI * dz[l]));
                const double v = double((OneSpecies ? wE11 : wE[a * side + b]) * fr[l] * r2s[l]);
                s.virial += v;
                s.virialVolume += double(in.isVolume[a] & in.isVolume[b]) * v;
                s.inRange += r2s[l] > 0;
                if constexpr (Energy) {
                    const double d2 = (in.e[j] - pi).squaredNorm();
                    if (r2s[l] > 0 && d2 < lj.cutoff2())
                        s.energy += (OneSpecies ? wE11d : kernel.ljEnergyWeights()[a * side + b]) * lj.energyOfR2(d2);
                }
            }
        }
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
    if (in.mixed) {
        if (one && !energies) loopMixed<true, false>(kernel, pairs, in, x0, x1, sums);
        if (one && energies) loopMixed<true, true>(kernel, pairs, in, x0, x1, sums);
        if (!one && !energies) loopMixed<false, false>(kernel, pairs, in, x0, x1, sums);
        if (!one && energies) loopMixed<false, true>(kernel, pairs, in, x0, x1, sums);
        return;
    }
    if (one && !energies) loop<true, false>(kernel, pairs, in, x0, x1, sums);
    if (one && energies) loop<true, true>(kernel, pairs, in, x0, x1, sums);
    if (!one && !energies) loop<false, false>(kernel, pairs, in, x0, x1, sums);
    if (!one && energies) loop<false, true>(kernel, pairs, in, x0, x1, sums);
}

}  // namespace bop::core
