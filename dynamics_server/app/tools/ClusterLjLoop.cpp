#include "ClusterLjLoop.hpp"

#include "core/SimdMath.hpp"
#include "core/TargetClones.hpp"

#include <algorithm>
#include <array>
#include <cstring>

namespace bop::tools {
namespace {

using namespace core;

using V8D = double __attribute__((vector_size(64)));
using V8L = std::int64_t __attribute__((vector_size(64)));
using V8F = float __attribute__((vector_size(32)));
constexpr std::uint32_t kC = ClusterPairs::kSize;
constexpr std::uint32_t kBlock = 32;  // cluster pairs of a row per pass

// Bit a of the index spread to bits 4a..4a + 3: an i cluster's flags over its lanes.
constexpr auto kRepeated = [] {
    std::array<std::uint32_t, 16> t{};
    for (std::uint32_t m = 0; m < 16; ++m)
        for (std::uint32_t a = 0; a < kC; ++a)
            if (m >> a & 1) t[m] |= 0xFu << (kC * a);
    return t;
}();

[[gnu::always_inline]] inline V4 load4(const double* p) {
    V4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
// Lane 4a + b of a cluster pair: i-side values repeated (lanes 0-7: a = 0, 1; 8-15: a = 2, 3),
// j-side values tiled (b).
[[gnu::always_inline]] inline V8D tiled(V4 v) {
    return __builtin_shufflevector(v, v, 0, 1, 2, 3, 0, 1, 2, 3);
}
[[gnu::always_inline]] inline V8D repeatedLo(V4 v) {
    return __builtin_shufflevector(v, v, 0, 0, 0, 0, 1, 1, 1, 1);
}
[[gnu::always_inline]] inline V8D repeatedHi(V4 v) {
    return __builtin_shufflevector(v, v, 2, 2, 2, 2, 3, 3, 3, 3);
}
[[gnu::always_inline]] inline V16F floats(V8D lo, V8D hi) {
    const V8F a = __builtin_convertvector(lo, V8F), b = __builtin_convertvector(hi, V8F);
    return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
}
[[gnu::always_inline]] inline V8D doublesLo(V16F v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1, 2, 3, 4, 5, 6, 7), V8D);
}
[[gnu::always_inline]] inline V8D doublesHi(V16F v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 8, 9, 10, 11, 12, 13, 14, 15), V8D);
}
// The lanes of one half whose bits are set: lane l of the low half is bit l, of the high bit 8 + l.
[[gnu::always_inline]] inline V8L bitLanes(std::uint32_t bits, int half) {
    const V8L one = {1, 2, 4, 8, 16, 32, 64, 128};
    return ((V8L{} + std::int64_t(bits >> (8 * half))) & one) != 0;
}
// v where the mask's lane is set, else 0 (bits, not a select: GCC made the select lane by lane).
[[gnu::always_inline]] inline V8D keep(V8L m, V8D v) {
    return (V8D)(m & (V8L)v);
}
// Lanes with x < y: the sign of x - y (exact: its sign is right whenever x != y, +0 when equal),
// spread over the lane. GCC compared these eight-double vectors lane by lane.
[[gnu::always_inline]] inline V8L below(V8D x, V8D y) {
    return (V8L)(x - y) >> 63;
}
// Sums over a of lanes 4a + b (lo: a = 0, 1; hi: a = 2, 3), b = 0..3; the same order every time.
[[gnu::always_inline]] inline V4 overA(V8D lo, V8D hi) {
    const V8D s = lo + hi;
    return __builtin_shufflevector(s, s, 0, 1, 2, 3) + __builtin_shufflevector(s, s, 4, 5, 6, 7);
}
// Sum over b of lanes 4a + b of its half (a = 0, 1 of lo or 2, 3 of hi): entry a's lanes.
[[gnu::always_inline]] inline double overB(V8D v, int a) {
    return (v[4 * a] + v[4 * a + 1]) + (v[4 * a + 2] + v[4 * a + 3]);
}

[[gnu::always_inline]] inline V8D load8(const double* p) {
    V8D v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void add4(double* p, V4 v) {
    const V4 now = load4(p) + v;
    std::memcpy(p, &now, sizeof now);
}

template <bool OneSpecies, bool Energy>
[[gnu::always_inline]] inline void loop(const PairKernel& kernel, const ClusterPairs& cp, const std::uint8_t* species,
                                        double* f, std::size_t c0, std::size_t c1, PairKernel::Sums& sums) {
    const LjForm lj = kernel.lj();
    const float fShift = float(lj.forceShift()), rOn = float(lj.switchOn()), invWidth = float(lj.invSwitchWidth());
    const V8D cut2 = V8D{} + lj.cutoff2(), three = V8D{} + 3.0;
    const std::size_t side = std::size_t(kernel.tableSide()), ne = cp.entryCount();
    const double* wF = kernel.ljForceWeights();
    const double* wE = kernel.ljEnergyWeights();
    const double wF11 = wF[side + 1], wE11 = wE[side + 1];
    const auto speciesOf = [&](std::size_t x) -> std::size_t { return x < ne ? species[x] : 0; };
    V8D virial = {}, virialVolume = {};
    V16FMask count = {};
    double energy = 0;
    alignas(64) double wJ[16], wI[16], wV[16], frs[16 * kBlock];
    for (std::size_t c = c0; c < c1; ++c) {
        const double* pi = cp.pos.data() + 3 * kC * c;
        const V4 xi = load4(pi), yi = load4(pi + 4), zi = load4(pi + 8);
        const V8D xa = repeatedLo(xi), xb = repeatedHi(xi), ya = repeatedLo(yi), yb = repeatedHi(yi),
                  za = repeatedLo(zi), zb = repeatedHi(zi);
        std::size_t si[kC];
        for (std::uint32_t a = 0; a < kC; ++a) si[a] = speciesOf(kC * c + a);
        const std::uint32_t volumeI = kRepeated[cp.volume[c]];
        V8D fxa = {}, fxb = {}, fya = {}, fyb = {}, fza = {}, fzb = {};
        for (std::uint32_t k0 = cp.start[c]; k0 < cp.start[c + 1]; k0 += kBlock) {
            const std::uint32_t n = std::min<std::uint32_t>(kBlock, cp.start[c + 1] - k0);
            // Pass 1: f(r)/r and the virial of each cluster pair, independent of each other.
            for (std::uint32_t q = 0; q < n; ++q) {
                const ClusterPairs::Entry en = cp.list[k0 + q];
                const double* pj = cp.pos.data() + 3 * kC * en.j;
                const V8D xj = tiled(load4(pj)), yj = tiled(load4(pj + 4)), zj = tiled(load4(pj + 8));
                const V8D dxa = xj - xa, dxb = xj - xb, dya = yj - ya, dyb = yj - yb, dza = zj - za, dzb = zj - zb;
                const V8D r2a = dxa * dxa + dya * dya + dza * dza, r2b = dxb * dxb + dyb * dyb + dzb * dzb;
                const V8L ina = below(r2a, cut2) & bitLanes(en.lanes, 0),
                          inb = below(r2b, cut2) & bitLanes(en.lanes, 1);
                const V16F r2 = floats(keep(ina, r2a), keep(inb, r2b));
                const V16F gap = floats(three - r2a, three - r2b);
                const V16FMask inside = r2 > splat16(0.0f);
                const V16F q2 = select(inside, r2, splat16(1.0f));
                const V16F inv2 = 1.0f / q2;
                const V16F r = vsqrt(q2), rinv = r * inv2;
                const V16F fa = 1.5f * gap * inv2 * inv2 - fShift;
                const V16F t = atLeast((r - rOn) * invWidth, 0.0f);
                const V16F fr = select(inside, fa * (1.0f + t * t * (2.0f * t - 3.0f)) * rinv, splat16(0.0f));
                const V8D fra = doublesLo(fr), frb = doublesHi(fr);
                std::memcpy(frs + 16 * q, &fra, sizeof fra);
                std::memcpy(frs + 16 * q + 8, &frb, sizeof frb);
                const std::size_t j0 = kC * std::size_t(en.j);
                V8D va, vb;
                if constexpr (OneSpecies) {
                    va = wE11 * fra * r2a, vb = wE11 * frb * r2b;
                } else {
                    for (std::uint32_t l = 0; l < 16; ++l) {
                        const std::size_t a = si[l / kC], b = speciesOf(j0 + l % kC);
                        wV[l] = wE[a * side + b];
                    }
                    va = load8(wV) * fra * r2a, vb = load8(wV + 8) * frb * r2b;
                }
                const std::uint32_t volume = volumeI & (0x1111u * cp.volume[en.j]);  // bit 4a + b: both volume
                virial += va + vb;
                virialVolume += keep(bitLanes(volume, 0), va) + keep(bitLanes(volume, 1), vb);
                count -= inside;  // a lane kept is -1
                if constexpr (Energy) {
                    for (std::uint32_t l = 0; l < 16; ++l) {
                        if (!inside[l]) continue;
                        const double d2 = l < 8 ? r2a[l] : r2b[l - 8];
                        const std::size_t a = si[l / kC], b = speciesOf(j0 + l % kC);
                        energy += wE[a * side + b] * lj.energyOfR2(d2);
                    }
                }
            }
            // Pass 2: the forces, from the differences again.
            for (std::uint32_t q = 0; q < n; ++q) {
                const ClusterPairs::Entry en = cp.list[k0 + q];
                const double* pj = cp.pos.data() + 3 * kC * en.j;
                const V8D xj = tiled(load4(pj)), yj = tiled(load4(pj + 4)), zj = tiled(load4(pj + 8));
                const V8D dxa = xj - xa, dxb = xj - xb, dya = yj - ya, dyb = yj - yb, dza = zj - za, dzb = zj - zb;
                const V8D fra = load8(frs + 16 * q), frb = load8(frs + 16 * q + 8);
                const std::size_t j0 = kC * std::size_t(en.j);
                V8D ja, jb, ia, ib;  // weighted f(r)/r to j and to i
                if constexpr (OneSpecies) {
                    ja = ia = wF11 * fra, jb = ib = wF11 * frb;
                } else {
                    for (std::uint32_t l = 0; l < 16; ++l) {
                        const std::size_t a = si[l / kC], b = speciesOf(j0 + l % kC);
                        wJ[l] = wF[b * side + a], wI[l] = wF[a * side + b];
                    }
                    ja = load8(wJ) * fra, jb = load8(wJ + 8) * frb;
                    ia = load8(wI) * fra, ib = load8(wI + 8) * frb;
                }
                fxa -= ia * dxa, fxb -= ib * dxb, fya -= ia * dya, fyb -= ib * dyb, fza -= ia * dza, fzb -= ib * dzb;
                double* fj = f + 3 * j0;
                add4(fj, overA(ja * dxa, jb * dxb));
                add4(fj + 4, overA(ja * dya, jb * dyb));
                add4(fj + 8, overA(ja * dza, jb * dzb));
            }
        }
        double* fi = f + 3 * kC * c;
        for (std::uint32_t a = 0; a < kC; ++a) {
            const int h = int(a % 2);
            fi[a] += overB(a < 2 ? fxa : fxb, h);
            fi[4 + a] += overB(a < 2 ? fya : fyb, h);
            fi[8 + a] += overB(a < 2 ? fza : fzb, h);
        }
    }
    for (int l = 0; l < 8; ++l) sums.virial += virial[l], sums.virialVolume += virialVolume[l];
    for (int l = 0; l < 16; ++l) sums.inRange += std::size_t(count[l]);
    sums.energy += energy;
}

}  // namespace

BOP_HOT_LOOP void ljClusterPairs(const core::PairKernel& kernel, const ClusterPairs& clusters,
                                 const std::uint8_t* species, double* f, bool energies, std::size_t c0, std::size_t c1,
                                 core::PairKernel::Sums& sums) {
    if (c0 >= c1) return;
    const bool one = kernel.tableSide() == 2 || kernel.ljUniform();
    if (one && !energies) loop<true, false>(kernel, clusters, species, f, c0, c1, sums);
    if (one && energies) loop<true, true>(kernel, clusters, species, f, c0, c1, sums);
    if (!one && !energies) loop<false, false>(kernel, clusters, species, f, c0, c1, sums);
    if (!one && energies) loop<false, true>(kernel, clusters, species, f, c0, c1, sums);
}

}  // namespace bop::tools
