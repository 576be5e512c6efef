#include "OrientedPairLoop.hpp"

#include "OrientedTerms.hpp"
#include "PairBlocks.hpp"
#include "TargetClones.hpp"

namespace bop::core {
namespace {

// One block's results per entry: force on j and on i, torque on i and on j.
struct Block {
    alignas(32) double fj[3][kPairBlock];
    alignas(32) double fi[3][kPairBlock];
    alignas(32) double ti[3][kPairBlock];
    alignas(32) double tj[3][kPairBlock];
};

// A species table's entries for four pairs.
[[gnu::always_inline]] inline V4 table4(const double* t, const std::size_t* k) {
    return V4{t[k[0]], t[k[1]], t[k[2]], t[k[3]]};
}

// Four pairs' vectors into a block's entries q..q+3, zero in the lanes not `near`.
[[gnu::always_inline]] inline void storeNear(double (&to)[3][kPairBlock], std::uint32_t q, V4Mask near,
                                             const Xyz<V4>& v) {
    const V4 zero = splat(0.0);
    store4(to[0] + q, select(near, v.x, zero));
    store4(to[1] + q, select(near, v.y, zero));
    store4(to[2] + q, select(near, v.z, zero));
}

// Where orientedPair's results for four pairs go: the block's entries q..q+3 and the lane sums,
// lanes not `near` zero.
struct BlockSink {
    Block& b;
    std::uint32_t q;
    V4Mask near;
    V4& virialSum;
    V4& energySum;
    [[gnu::always_inline]] void fj(const Xyz<V4>& v) { storeNear(b.fj, q, near, v); }
    [[gnu::always_inline]] void fi(const Xyz<V4>& v) { storeNear(b.fi, q, near, v); }
    [[gnu::always_inline]] void ti(const Xyz<V4>& v) { storeNear(b.ti, q, near, v); }
    [[gnu::always_inline]] void tj(const Xyz<V4>& v) { storeNear(b.tj, q, near, v); }
    [[gnu::always_inline]] void virial(V4 v) { virialSum += select(near, v, splat(0.0)); }
    [[gnu::always_inline]] void energy(V4 v) { energySum += select(near, v, splat(0.0)); }
};

// One: every pair with oriented weights has the same (one bag's surface, or several bags' at one
// set of parameters), held throughout; with several oriented species, the pairs without weights
// (two bags' surfaces, when the list holds them) are masked out.
template <bool Energy, bool One>
[[gnu::always_inline]] inline void loop(const PairKernel& kernel, const NeighbourList::Pairs& pairs,
                                        const PairInputs& in, const OrientedInputs& o, std::size_t x0, std::size_t x1,
                                        PairKernel::Sums& sums) {
    const OrientedWeight& w = kernel.weight();
    const PairKernel::OrientedTables tab = kernel.orientedTables();
    const std::size_t side = std::size_t(kernel.tableSide());
    const std::size_t single = std::size_t(std::max(kernel.uniformOrientedPair(), 0));
    const bool maskOff = kernel.singleOrientedSpecies() == 0;  // several oriented species
    // The single species' weights, copied: the force stores may alias the tables.
    const double cnF1 = tab.cnF[single], cpF1 = tab.cpF[single], cnT1 = tab.cnT[single], cpT1 = tab.cpT[single];
    const double cnE1 = tab.cnE[single], cpE1 = tab.cpE[single];
    const double cut2 = w.cutoff2();
    const PsiConstants psiK = w.constants();
    const bool curvature = kernel.curvature();
    const double* e = in.e[0].data();
    const double* nrm = o.normal[0].data();
    const float* cw = o.curvature;
    const std::uint8_t* sp = in.species;
    double* f = in.f[0].data() - 3 * in.base;
    double* tq = o.t[0].data() - 3 * in.base;
    const V4 zero = splat(0.0);
    V4 energy = zero, virial = zero;
    V4Mask count = V4Mask{0, 0, 0, 0};
    Block b;
    PairBlocks blocks(pairs, x0, x1);
    RowSums into{f, tq};
    std::uint32_t k0 = 0;
    for (std::uint32_t n; (n = blocks.next(k0)) > 0;) {
        for (std::uint32_t q = 0; q < n; q += 4) {
            const std::uint32_t* iq = blocks.i + q;
            const std::uint32_t* jq = blocks.j(q);
            const V4 rx = gather3(e, jq, 0) - gather3(e, iq, 0), ry = gather3(e, jq, 1) - gather3(e, iq, 1),
                     rz = gather3(e, jq, 2) - gather3(e, iq, 2);
            const V4 r2 = rx * rx + ry * ry + rz * rz;
            OrientedWeights<V4> k{splat(cnF1), splat(cnF1), splat(cnT1), splat(cnT1), splat(cnE1),
                                  splat(cpF1), splat(cpF1), splat(cpT1), splat(cpT1), splat(cpE1)};
            V4Mask near = lanes(q, n) & (r2 < cut2);
            if constexpr (One) {
                if (maskOff)
                    near &= V4Mask{tab.on[sp[iq[0]] * side + sp[jq[0]]], tab.on[sp[iq[1]] * side + sp[jq[1]]],
                                   tab.on[sp[iq[2]] * side + sp[jq[2]]], tab.on[sp[iq[3]] * side + sp[jq[3]]]} != 0;
            } else {
                std::size_t ab[4], ba[4];
                for (int l = 0; l < 4; ++l) {
                    ab[l] = sp[iq[l]] * side + sp[jq[l]];
                    ba[l] = sp[jq[l]] * side + sp[iq[l]];
                }
                k = {table4(tab.cnF, ab), table4(tab.cnF, ba), table4(tab.cnT, ab), table4(tab.cnT, ba),
                     table4(tab.cnE, ab), table4(tab.cpF, ab), table4(tab.cpF, ba), table4(tab.cpT, ab),
                     table4(tab.cpT, ba), table4(tab.cpE, ab)};
                near &= V4Mask{tab.on[ab[0]], tab.on[ab[1]], tab.on[ab[2]], tab.on[ab[3]]} != 0;
            }
            const V4 rlen = vsqrt(r2);
            const Xyz<V4> r{rx, ry, rz};
            const Xyz<V4> ni{gather3(nrm, iq, 0), gather3(nrm, iq, 1), gather3(nrm, iq, 2)};
            const Xyz<V4> nj{gather3(nrm, jq, 0), gather3(nrm, jq, 1), gather3(nrm, jq, 2)};
            V4 c = splat(1.0);  // the co-planar curvature weight: the mean of the two
            if (curvature)
                for (int l = 0; l < 4; ++l) c[l] = 0.5 * (double(cw[iq[l]]) + double(cw[jq[l]]));
            BlockSink sink{b, q, near, virial, energy};
            orientedPair<Energy>(r, r2, inverseOrZero(rlen), normalPair(r, ni, nj), orientedPsi(r2, rlen, psiK), c, k,
                                 sink);
            count -= near;  // a true lane is -1
        }
        into.add(b, blocks.i, pairs.nbr.data() + k0, n);  // into the particles, in list order
    }
    into.finish();
    sums.energy += laneSum(energy);
    sums.virial += laneSum(virial);
    sums.orientedInRange += std::size_t(count[0] + count[1] + count[2] + count[3]);
}

}  // namespace

BOP_HOT_LOOP void orientedPairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                                const OrientedInputs& o, bool energies, std::size_t x0, std::size_t x1,
                                PairKernel::Sums& sums) {
    if (pairs.start.size() < 2 || x0 >= x1) return;
    if (in.mixed) return orientedPairsMixed(kernel, pairs, in, o, energies, x0, x1, sums);
    const bool one = kernel.uniformOrientedPair() >= 0;
    if (energies && one) loop<true, true>(kernel, pairs, in, o, x0, x1, sums);
    if (energies && !one) loop<true, false>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && one) loop<false, true>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && !one) loop<false, false>(kernel, pairs, in, o, x0, x1, sums);
}

}  // namespace bop::core
