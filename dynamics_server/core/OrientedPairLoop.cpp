#include "OrientedPairLoop.hpp"

#include "HotLoop.hpp"

#include <cmath>

namespace bop::core {
namespace {

// The weights of one ordered species pair (a, b): force and torque to each side, energy.
struct PairWeights {
    double cnFab, cnFba, cpFab, cpFba, cnTab, cnTba, cpTab, cpTba, cnE, cpE;
};

PairWeights weightsOf(const PairKernel::OrientedTables& t, std::size_t ab, std::size_t ba) {
    return {t.cnF[ab], t.cnF[ba], t.cpF[ab], t.cpF[ba], t.cnT[ab],
            t.cnT[ba], t.cpT[ab], t.cpT[ba], t.cnE[ab], t.cpE[ab]};
}

// One: every pair is of the one oriented species (a bag's surface), its weights held throughout.
template <bool Energy, bool One>
[[gnu::always_inline]] inline void loop(const PairKernel& kernel, const NeighbourList::Pairs& pairs,
                                        const PairInputs& in, const OrientedInputs& o, std::size_t x0, std::size_t x1,
                                        PairKernel::Sums& sums) {
    const OrientedWeight& w = kernel.weight();
    const PairKernel::OrientedTables tab = kernel.orientedTables();
    const std::size_t side = std::size_t(kernel.tableSide());
    const std::size_t single = std::size_t(kernel.singleOrientedSpecies()) * (side + 1);
    const PairWeights one = weightsOf(tab, single, single);
    const double cut2 = w.cutoff2(), rOn = w.taperOn(), invWidth = w.invTaperWidth();
    const double inv2s2 = w.invTwoSigma2(), invS2 = w.invSigma2();
    const bool curvature = kernel.curvature();
    const std::uint32_t* nbr = pairs.nbr.data();
    const std::uint32_t* start = pairs.start.data();
    PairKernel::Sums s;
    for (std::size_t x = x0; x < x1; ++x) {
        const std::uint32_t k0 = start[x], k1 = start[x + 1];
        if (k0 == k1) continue;
        const Eigen::Vector3d pi = in.e[x], ni = o.normal[x];  // copies: the stores may alias
        const std::size_t a = in.species[x];
        const double wi = double(o.curvature[x]);
        Eigen::Vector3d fi = Eigen::Vector3d::Zero(), ti = Eigen::Vector3d::Zero();
        for (std::uint32_t k = k0; k < k1; ++k) {
            const std::uint32_t y = nbr[k];
            const Eigen::Vector3d r = in.e[y] - pi;
            const double r2 = r.squaredNorm();
            if (r2 >= cut2) continue;
            PairWeights pw = one;
            if constexpr (!One) {
                const std::size_t b = in.species[y], ab = a * side + b, ba = b * side + a;
                if (!tab.on[ab]) continue;
                pw = weightsOf(tab, ab, ba);
            }
            ++s.orientedInRange;
            const double rlen = std::sqrt(r2);
            const double invR = rlen > 0.0 ? 1.0 / rlen : 0.0;
            // psi = exp(-r^2 / 2 sigma^2) S(r) and its derivative, S the cubic taper.
            const double g = std::exp(-rlen * rlen * inv2s2);
            const double u = (rlen - rOn) * invWidth;
            const double t = u > 0.0 ? u : 0.0;
            const double taper = 1.0 + t * t * (2.0 * t - 3.0);
            const double psi = g * taper;
            const double dpsi = (-rlen * invS2 * g) * taper + g * (6.0 * t * (t - 1.0) * invWidth);
            const Eigen::Vector3d nj = o.normal[y];
            // Co-normal |n_i - n_j|^2 psi.
            const double d2 = (ni - nj).squaredNorm();
            const Eigen::Vector3d cnF = (-d2 * dpsi * invR) * r;
            const Eigen::Vector3d cnTi = (2.0 * psi) * ni.cross(nj);
            // Co-planar ((n_i.r)^2 + (n_j.r)^2) c psi, c the mean curvature weight of the two.
            const double c = curvature ? 0.5 * (wi + double(o.curvature[y])) : 1.0;
            const double cpsi = c * psi, cdpsi = c * dpsi;
            const double A = ni.dot(r), B = nj.dot(r), ab2 = A * A + B * B;
            const Eigen::Vector3d cpF = (-2.0 * cpsi) * (A * ni + B * nj) - (ab2 * cdpsi * invR) * r;
            in.f[y - in.base] += pw.cnFba * cnF + pw.cpFba * cpF;
            fi -= pw.cnFab * cnF + pw.cpFab * cpF;
            ti += pw.cnTab * cnTi + pw.cpTab * ((2.0 * A * cpsi) * r.cross(ni));
            o.t[y - in.base] += pw.cnTba * -cnTi + pw.cpTba * ((2.0 * B * cpsi) * r.cross(nj));
            s.virial += pw.cnE * r.dot(cnF) + pw.cpE * r.dot(cpF);
            if constexpr (Energy) s.energy += pw.cnE * (d2 * psi) + pw.cpE * (ab2 * cpsi);
        }
        in.f[x - in.base] += fi;
        o.t[x - in.base] += ti;
    }
    sums.energy += s.energy;
    sums.virial += s.virial;
    sums.orientedInRange += s.orientedInRange;
}

}  // namespace

BOP_HOT_LOOP void orientedPairs(const PairKernel& kernel, const NeighbourList::Pairs& pairs, const PairInputs& in,
                                const OrientedInputs& o, bool energies, std::size_t x0, std::size_t x1,
                                PairKernel::Sums& sums) {
    if (pairs.start.size() < 2 || x0 >= x1) return;
    const bool one = kernel.singleOrientedSpecies() > 0;
    if (energies && one) loop<true, true>(kernel, pairs, in, o, x0, x1, sums);
    if (energies && !one) loop<true, false>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && one) loop<false, true>(kernel, pairs, in, o, x0, x1, sums);
    if (!energies && !one) loop<false, false>(kernel, pairs, in, o, x0, x1, sums);
}

}  // namespace bop::core
