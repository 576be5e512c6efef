// The oriented loop in mixed precision (PairInputs::mixed): OrientedPairLoop.cpp's blocks, sixteen
// entries at a time in float lanes (V16F). Four at a time in double, each entry's difference of
// the positions, r^2, and what the terms take from the normals (normalPair: n_i - n_j, n_i x n_j,
// n_i.r, n_j.r, small near rest) are worked out and rounded to float; OrientedTerms.hpp's physics
// runs in float; each entry's forces, torques, virial and energy go into the double sums in list
// order, so the sums do not depend on the thread count.
#include "OrientedPairLoop.hpp"
#include "OrientedTerms.hpp"
#include "PairBlocks.hpp"
#include "TargetClones.hpp"

#include <cstring>

namespace bop::core {
namespace {

constexpr std::uint32_t kLanes16 = 16;
static_assert(kPairBlock % kLanes16 == 0);

// One block's results per entry in float: forces on j and i, torques on i and j, virial, energy.
struct Block32 {
    alignas(64) float fj[3][kPairBlock];
    alignas(64) float fi[3][kPairBlock];
    alignas(64) float ti[3][kPairBlock];
    alignas(64) float tj[3][kPairBlock];
    alignas(64) float virial[kPairBlock];
    alignas(64) float energy[kPairBlock];
};

// Where orientedPair's results for sixteen entries go: the block's entries q..q+15, lanes not
// `near` zero.
struct Sink16 {
    Block32& b;
    std::uint32_t q;
    V16FMask near;
    [[gnu::always_inline]] V16F keep(V16F v) const { return select(near, v, splat16(0.0f)); }
    [[gnu::always_inline]] void put(float (&to)[3][kPairBlock], const Xyz<V16F>& v) const {
        store16(to[0] + q, keep(v.x));
        store16(to[1] + q, keep(v.y));
        store16(to[2] + q, keep(v.z));
    }
    [[gnu::always_inline]] void fj(const Xyz<V16F>& v) { put(b.fj, v); }
    [[gnu::always_inline]] void fi(const Xyz<V16F>& v) { put(b.fi, v); }
    [[gnu::always_inline]] void ti(const Xyz<V16F>& v) { put(b.ti, v); }
    [[gnu::always_inline]] void tj(const Xyz<V16F>& v) { put(b.tj, v); }
    [[gnu::always_inline]] void virial(V16F v) { store16(b.virial + q, keep(v)); }
    [[gnu::always_inline]] void energy(V16F v) { store16(b.energy + q, keep(v)); }
};

// One lane group's inputs, gathered: r, the normals and what normalPair takes from them, each
// worked out in double and rounded to float (near rest these are small differences of large
// numbers), r^2 likewise, the curvature weight, the entry's
// oriented weights (per lane when the pairs' species differ, OrientedWeights' fields in order)
// and whether it counts (valid, with weights, within the cutoff in double: all ones, else 0).
struct Lanes16 {
    alignas(64) float r[3][kLanes16], ni[3][kLanes16], nj[3][kLanes16], d[3][kLanes16], nn[3][kLanes16];
    alignas(64) float r2[kLanes16], cosine[kLanes16], A[kLanes16], B[kLanes16], c[kLanes16];
    alignas(64) float w[10][kLanes16];
    alignas(64) std::int32_t on[kLanes16];
};

template <bool Energy, bool One>
[[gnu::always_inline]] inline void loop(const PairKernel& kernel, const NeighbourList::Pairs& pairs,
                                        const PairInputs& in, const OrientedInputs& o, std::size_t x0, std::size_t x1,
                                        PairKernel::Sums& sums) {
    const OrientedWeight& w = kernel.weight();
    const PairKernel::OrientedTables32 tab = kernel.orientedTables32();
    const std::size_t side = std::size_t(kernel.tableSide());
    const std::size_t single = std::size_t(std::max(kernel.uniformOrientedPair(), 0));
    const double cut2 = w.cutoff2();
    const PsiConstantsOf<float> psiK = toFloat(w.constants());
    const bool curvature = kernel.curvature();
    const double* e = in.e[0].data();
    const double* nrm = o.normal[0].data();
    const float* cw = o.curvature;
    const std::uint8_t* sp = in.species;
    double* f = in.f[0].data() - 3 * in.base;
    double* tq = o.t[0].data() - 3 * in.base;
    const float* tables[10] = {tab.cnF, tab.cnF, tab.cnT, tab.cnT, tab.cnE,
                               tab.cpF, tab.cpF, tab.cpT, tab.cpT, tab.cpE};
    const bool swapped[10] = {false, true, false, true, false, false, true, false, true, false};  // ba, not ab
    const auto one = [&](int t) { return splat16(tables[t][single]); };
    const OrientedWeights<V16F> k1{one(0), one(1), one(2), one(3), one(4), one(5), one(6), one(7), one(8), one(9)};
    double energy = 0, virial = 0;
    std::size_t count = 0;
    Block32 b;
    Lanes16 g;
    PairBlocks blocks(pairs, x0, x1);
    RowSums into{f, tq};
    std::uint32_t k0 = 0;
    for (std::uint32_t n; (n = blocks.next(k0)) > 0;) {
        const std::uint32_t* nb = pairs.nbr.data() + k0;
        for (std::uint32_t q = 0; q < n; q += kLanes16) {
            for (std::uint32_t l0 = 0; l0 < kLanes16; l0 += 4) {  // four lanes at a time in double
                std::uint32_t iq[4], jq[4];
                for (std::uint32_t l = 0; l < 4; ++l) {  // lanes past n pair the last row with itself
                    const std::uint32_t at = q + l0 + l;
                    const bool valid = at < n;
                    iq[l] = blocks.i[valid ? at : n - 1];
                    jq[l] = valid ? nb[at] : iq[l];
                    const std::size_t i = iq[l], j = jq[l], ab = sp[i] * side + sp[j], ba = sp[j] * side + sp[i];
                    g.c[l0 + l] = curvature ? 0.5f * (cw[i] + cw[j]) : 1.0f;
                    g.on[l0 + l] = valid && tab.on[ab] ? -1 : 0;  // pairs without weights masked out
                    if constexpr (!One)
                        for (int t = 0; t < 10; ++t) g.w[t][l0 + l] = tables[t][swapped[t] ? ba : ab];
                }
                const Xyz<V4> r{gather3(e, jq, 0) - gather3(e, iq, 0), gather3(e, jq, 1) - gather3(e, iq, 1),
                                gather3(e, jq, 2) - gather3(e, iq, 2)};
                const Xyz<V4> ni{gather3(nrm, iq, 0), gather3(nrm, iq, 1), gather3(nrm, iq, 2)};
                const Xyz<V4> nj{gather3(nrm, jq, 0), gather3(nrm, jq, 1), gather3(nrm, jq, 2)};
                const NormalPair<V4> np = normalPair(r, ni, nj);
                const auto put = [l0](float(&to)[3][kLanes16], const Xyz<V4>& v) {
                    toFloats(to[0] + l0, v.x), toFloats(to[1] + l0, v.y), toFloats(to[2] + l0, v.z);
                };
                put(g.r, r), put(g.ni, ni), put(g.nj, nj), put(g.d, np.d), put(g.nn, np.nn);
                const V4 r2 = dot(r, r);
                toFloats(g.r2 + l0, r2);
                const V4Mask inside = r2 < splat(cut2);  // in double: the count is double's
                for (std::uint32_t l = 0; l < 4; ++l) g.on[l0 + l] &= std::int32_t(inside[l]);
                toFloats(g.cosine + l0, np.cosine), toFloats(g.A + l0, np.A), toFloats(g.B + l0, np.B);
            }
            const auto xyz = [](const float(&v)[3][kLanes16]) {
                return Xyz<V16F>{load16(v[0]), load16(v[1]), load16(v[2])};
            };
            const Xyz<V16F> r = xyz(g.r);
            const V16F r2 = load16(g.r2);
            V16FMask near;  // a valid entry with oriented weights within the cutoff
            std::memcpy(&near, g.on, sizeof near);
            OrientedWeights<V16F> k = k1;
            if constexpr (!One) {
                const auto at = [&](int t) { return load16(g.w[t]); };
                k = {at(0), at(1), at(2), at(3), at(4), at(5), at(6), at(7), at(8), at(9)};
            }
            const V16F rlen = vsqrt(r2);
            const NormalPair<V16F> np{xyz(g.ni),        xyz(g.nj),   xyz(g.d),   xyz(g.nn),
                                      load16(g.cosine), load16(g.A), load16(g.B)};
            Sink16 sink{b, q, near};
            orientedPair<Energy>(r, r2, inverseOrZero(rlen), np, orientedPsi(r2, rlen, psiK), load16(g.c), k, sink);
            for (std::uint32_t l = 0; l < kLanes16; ++l) count += near[l] != 0;
        }
        into.add(b, blocks.i, nb, n);  // into the particles in double, in list order
        for (std::uint32_t q = 0; q < n; ++q) {
            virial += double(b.virial[q]);
            if constexpr (Energy) energy += double(b.energy[q]);
        }
    }
    into.finish();
    sums.energy += energy;
    sums.virial += virial;
    sums.orientedInRange += count;
}

}  // namespace

BOP_HOT_LOOP void orientedPairsMixed(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                                     const OrientedInputs& o, bool energies, std::size_t x0, std::size_t x1,
                                     PairKernel::Sums& sums) {
    if (pairs.start.size() < 2 || x0 >= x1) return;
    const bool one = kernel.uniformOrientedPair() >= 0;
    if (energies && one) loop<true, true>(kernel, pairs, in, o, x0, x1, sums);
    if (energies && !one) loop<true, false>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && one) loop<false, true>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && !one) loop<false, false>(kernel, pairs, in, o, x0, x1, sums);
}

}  // namespace bop::core
