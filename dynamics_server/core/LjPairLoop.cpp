#include "LjPairLoop.hpp"

#include "PairBlocks.hpp"
#include "TargetClones.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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
static_assert(kPairBlock % kLanes == 0);

// LjForm::forceOverR's constants rounded to float.
struct Lj32 {
    float fShift, rOn, invWidth;
    explicit Lj32(const LjForm& lj)
        : fShift(float(lj.forceShift())), rOn(float(lj.switchOn())), invWidth(float(lj.invSwitchWidth())) {}
};

// The entries of a block (PairBlocks.hpp: across rows, so that short rows leave no lanes idle),
// sixteen at a time: each difference of the double positions rounded to float, f(r)/r in float
// lanes, then each entry's force and virial into the double sums in list order.
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
    PairKernel::Sums s;
    const double cut2 = lj.cutoff2();
    alignas(64) float dx[kPairBlock], dy[kPairBlock], dz[kPairBlock], fr[kPairBlock], r2s[kPairBlock], gap[kPairBlock];
    const double* e = in.e[0].data();
    PairBlocks blocks(pairs, x0, x1);
    std::size_t row = ~std::size_t(0);
    Eigen::Vector3d fi = Eigen::Vector3d::Zero();
    std::uint32_t k0 = 0;
    for (std::uint32_t n; (n = blocks.next(k0)) > 0;) {
        const std::uint32_t* nb = pairs.nbr.data() + k0;
        const std::uint32_t padded = (n + kLanes - 1) / kLanes * kLanes;
        for (std::uint32_t q = 0; q < padded; q += 4) {  // four entries at a time in double
            std::uint32_t iq[4], jq[4];
            for (std::uint32_t l = 0; l < 4; ++l) {  // entries past n pair the last row with itself
                iq[l] = blocks.i[q + l < n ? q + l : n - 1];
                jq[l] = q + l < n ? nb[q + l] : iq[l];
            }
            const V4 x = gather3(e, jq, 0) - gather3(e, iq, 0), y = gather3(e, jq, 1) - gather3(e, iq, 1),
                     z = gather3(e, jq, 2) - gather3(e, iq, 2);
            const V4 d2 = x * x + y * y + z * z;
            toFloats(dx + q, x), toFloats(dy + q, y), toFloats(dz + q, z);
            // r^2 and 3 - r^2 (f(r) = 1.5 (3 - r^2) / r^4, 0 at r0^2 = 3) rounded from double:
            // near rest, where bags sit, the subtraction in float would lose most of the digits.
            const V4Mask inside = (d2 < splat(cut2)) & (d2 > splat(0.0)) & lanes(q, n);
            toFloats(r2s + q, select(inside, d2, splat(0.0)));
            toFloats(gap + q, 3.0 - d2);
        }
        for (std::uint32_t q = 0; q < padded; q += kLanes) {  // LjForm::forceOverR in float, 0 beyond the cutoff
            const V16F r2 = load16(r2s + q);
            const V16FMask inside = r2 > splat16(0.0f);  // compared with a vector: a scalar makes GCC go lane by lane
            const V16F q2 = select(inside, r2, splat16(1.0f));
            const V16F inv2 = 1.0f / q2;
            const V16F r = vsqrt(q2);
            const V16F f = 1.5f * load16(gap + q) * inv2 * inv2 - c.fShift;
            const V16F t = atLeast((r - c.rOn) * c.invWidth, 0.0f);
            store16(fr + q, select(inside, f * (1.0f + t * t * (2.0f * t - 3.0f)) * (r * inv2), splat16(0.0f)));
        }
        for (std::uint32_t q = 0; q < n; ++q) {  // in list order, into the double sums
            const std::size_t x = blocks.i[q];
            if (x != row) {
                if (row != ~std::size_t(0)) in.f[row - in.base] += fi;
                row = x;
                fi.setZero();
            }
            const std::uint32_t j = nb[q];
            const std::size_t a = in.species[x], b = in.species[j];
            const float toJ = (OneSpecies ? wF11 : wF[b * side + a]) * fr[q];
            const float toI = (OneSpecies ? wF11 : wF[a * side + b]) * fr[q];
            in.f[j - in.base] += Eigen::Vector3d(double(toJ * dx[q]), double(toJ * dy[q]), double(toJ * dz[q]));
            fi -= Eigen::Vector3d(double(toI * dx[q]), double(toI * dy[q]), double(toI * dz[q]));
            const double v = double((OneSpecies ? wE11 : wE[a * side + b]) * fr[q] * r2s[q]);
            s.virial += v;
            s.virialVolume += double(in.isVolume[a] & in.isVolume[b]) * v;
            s.inRange += r2s[q] > 0;
            if constexpr (Energy) {
                const double d2 = (in.e[j] - in.e[x]).squaredNorm();
                if (r2s[q] > 0)
                    s.energy += (OneSpecies ? wE11d : kernel.ljEnergyWeights()[a * side + b]) * lj.energyOfR2(d2);
            }
        }
    }
    if (row != ~std::size_t(0)) in.f[row - in.base] += fi;
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
