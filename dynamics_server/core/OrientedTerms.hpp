#pragma once
// The oriented pair physics, written once (docs/physics.md §1.2): the weight psi(r) =
// exp(-r^2 / 2 sigma^2) S(r) with its derivative, and the weighted co-normal and co-planar
// forces, torques, virial and energy of a pair. Templates over the number type T: double for the
// reference (OrientedWeight::eval, coNormal, coPlanar, PairKernel::apply), V4, four pairs in
// lanes, for the step's loop (OrientedPairLoop.cpp), and V16F, sixteen pairs in float lanes, for
// the mixed-precision loop (OrientedPairLoopMixed.cpp). The same expressions in the same order in
// all, so double and V4 differ only by e^x (std::exp against simdExp, a few ulp apart).
//
// Units as Potentials.hpp: lengths in simulation units, r = p_j - p_i, torques tau = -n x dE/dn.
#include "SimdMath.hpp"

#include <cmath>

namespace bop::core {

// Three components of one type: a vector of one pair (T = double) or of four (T = V4).
template <class T>
struct Xyz {
    T x, y, z;
};

template <class T>
[[gnu::always_inline]] inline T dot(const Xyz<T>& a, const Xyz<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
[[gnu::always_inline]] inline Xyz<T> cross(const Xyz<T>& a, const Xyz<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

[[gnu::always_inline]] inline double naturalExp(double x) {
    return std::exp(x);
}
[[gnu::always_inline]] inline V4 naturalExp(V4 x) {
    return simdExp(x);
}
[[gnu::always_inline]] inline V16F naturalExp(V16F x) {
    return simdExp(x);
}
// 1 / x, and 0 for x = 0 (dpsi -> 0 as r -> 0 for the Gaussian, so the force does too)
[[gnu::always_inline]] inline double inverseOrZero(double x) {
    return x > 0.0 ? 1.0 / x : 0.0;
}
[[gnu::always_inline]] inline V4 inverseOrZero(V4 x) {
    return select(x > 0.0, 1.0 / x, splat(0.0));
}
[[gnu::always_inline]] inline V16F inverseOrZero(V16F x) {
    return select(x > 0.0f, 1.0f / x, splat16(0.0f));
}

// The weight's constants (OrientedWeight holds them): all lengths in simulation units. S is
// double, or float for the float lanes.
template <class S>
struct PsiConstantsOf {
    S taperOn;        // start of the cubic taper, length
    S invTaperWidth;  // 1 / (cutoff - taperOn), 1/length
    S invTwoSigma2;   // 1 / (2 sigma^2), 1/length^2
    S invSigma2;      // 1 / sigma^2, 1/length^2
};
using PsiConstants = PsiConstantsOf<double>;
// The same rounded to float.
inline PsiConstantsOf<float> toFloat(const PsiConstants& k) {
    return {float(k.taperOn), float(k.invTaperWidth), float(k.invTwoSigma2), float(k.invSigma2)};
}

template <class T>
struct Psi {
    T psi;   // dimensionless
    T dpsi;  // dpsi/dr, 1/length
};

// psi and dpsi/dr at distance r (r2 = r^2) inside the cutoff, without branches: below the taper t
// clamps to 0, where S = 1 and dS = 0 exactly.
template <class T, class S>
[[gnu::always_inline]] inline Psi<T> orientedPsi(T r2, T r, const PsiConstantsOf<S>& k) {
    const T g = naturalExp(-r2 * k.invTwoSigma2);
    const T t = atLeast((r - k.taperOn) * k.invTaperWidth, 0.0);
    const T taper = 1.0 + t * t * (2.0 * t - 3.0);
    return {g * taper, (-r * k.invSigma2 * g) * taper + g * (6.0 * t * (t - 1.0) * k.invTaperWidth)};
}

// A pair's weights per term and side (PairKernel's tables, eqs. 2-3 and 6-8): F force, T torque,
// ab to i from j, ba to j from i; E the symmetrised weight of the energy and virial.
template <class T>
struct OrientedWeights {
    T cnFab, cnFba, cnTab, cnTba, cnE;  // co-normal
    T cpFab, cpFba, cpTab, cpTba, cpE;  // co-planar
};

template <class T>
struct OrientedForces {
    Xyz<T> fj, fi;  // forces on j and on i (energy/length)
    Xyz<T> ti, tj;  // torques on i and on j (energy)
    T virial;       // r . F_j of each term, weighted (energy)
    T energy;       // |n_i - n_j|^2 psi + ((n_i.r)^2 + (n_j.r)^2) c psi, weighted (energy)
};

// The same-sheet gate g(c) of a pair, c = n_i.n_j: 1 while the normals are within 60 degrees
// (c >= 1/2), 0 from 120 degrees apart on (c <= -1/2), the quintic smootherstep between (its
// first and second derivatives vanish at both ends, so the dynamics meets no kink; a narrower
// band made an undamped cluster's energy drift past 1e-3); dg = dg/dc.
// Particles on opposite faces of a part thinner than the weight's reach, or across a narrow gap,
// face opposite ways and are not bent toward one another (docs/physics.md §1.1).
template <class T>
struct SheetGate {
    T g, dg;
};
template <class T>
[[gnu::always_inline]] inline SheetGate<T> sheetGate(T c) {
    const T t = atMost(atLeast(c + 0.5, 0.0), 1.0);
    const T u = 1.0 - t;
    return {t * t * t * (10.0 - 15.0 * t + 6.0 * t * t), 30.0 * t * t * u * u};
}

// A pair's unit normals and what the terms take from them and r = p_j - p_i: the quantities
// that are small where a sheet is smooth (n_i - n_j, n_i x n_j, n_i.r, n_j.r), worked out in one
// place so that the mixed-precision loop can take them from double.
template <class T>
struct NormalPair {
    Xyz<T> ni, nj;
    Xyz<T> d;   // n_i - n_j
    Xyz<T> nn;  // n_i x n_j
    T cosine;   // n_i . n_j
    T A, B;     // n_i . r, n_j . r
};
template <class T>
[[gnu::always_inline]] inline NormalPair<T> normalPair(const Xyz<T>& r, const Xyz<T>& ni, const Xyz<T>& nj) {
    return {ni, nj, Xyz<T>{ni.x - nj.x, ni.y - nj.y, ni.z - nj.z}, cross(ni, nj), dot(ni, nj), dot(ni, r), dot(nj, r)};
}

// Co-normal E = |n_i - n_j|^2 psi and co-planar E = ((n_i.r)^2 + (n_j.r)^2) c psi with their
// weights, both times the same-sheet gate g(n_i.n_j). r = p_j - p_i, r2 = |r|^2, invR = 1/|r|
// (0 at r = 0); n the unit normals (normalPair); c the co-planar curvature weight (1 without a map). Each
// result goes to `out` as soon as it is made (out.fj, fi, ti, tj with an Xyz<T>, out.virial and,
// when Energy, out.energy with a T), so that the vector loop stores each one before the next is
// made (fewer registers live).
template <bool Energy, class T, class Sink>
[[gnu::always_inline]] inline void orientedPair(const Xyz<T>& r, T r2, T invR, const NormalPair<T>& n, const Psi<T>& w,
                                                T c, const OrientedWeights<T>& k, Sink& out) {
    const Xyz<T>&ni = n.ni, &nj = n.nj;
    // The gate scales psi and its derivative; its own torque, -n_i x dg/dn_i E = -dg E n_i x n_j
    // on i and its opposite on j, is added to the co-normal torques below.
    const SheetGate<T> gate = sheetGate(n.cosine);
    const T psi = gate.g * w.psi, dpsi = gate.g * w.dpsi;
    // Co-normal: force on j -d2 dpsi r / |r|, torque 2 psi n_i x n_j on i and its opposite on j.
    const T d2 = dot(n.d, n.d);
    const T cn = -d2 * dpsi * invR;
    // Co-planar with A = n_i.r, B = n_j.r: force on j -2 c psi (A n_i + B n_j) - (A^2 + B^2) c dpsi
    // r / |r|; torques 2 A c psi r x n_i on i and 2 B c psi r x n_j on j.
    const T cpsi = c * psi, cdpsi = c * dpsi;
    const T A = n.A, B = n.B;
    const T ab2 = A * A + B * B;
    const T cpN = -2.0 * cpsi, cpR = -ab2 * cdpsi * invR;
    const Xyz<T> cp{cpN * (A * ni.x + B * nj.x) + cpR * r.x, cpN * (A * ni.y + B * nj.y) + cpR * r.y,
                    cpN * (A * ni.z + B * nj.z) + cpR * r.z};
    out.fj(Xyz<T>{k.cnFba * cn * r.x + k.cpFba * cp.x, k.cnFba * cn * r.y + k.cpFba * cp.y,
                  k.cnFba * cn * r.z + k.cpFba * cp.z});
    out.fi(Xyz<T>{-(k.cnFab * cn * r.x + k.cpFab * cp.x), -(k.cnFab * cn * r.y + k.cpFab * cp.y),
                  -(k.cnFab * cn * r.z + k.cpFab * cp.z)});
    // Around n_i x n_j: the co-normal torque 2 psi and the gate's -dg (E_CN + E_CP) of each side.
    const Xyz<T>& nn = n.nn;
    const T eCn = d2 * w.psi, eCp = ab2 * c * w.psi;  // ungated energies of the two terms
    const T p2 = 2.0 * psi;
    const T si = k.cnTab * (p2 - gate.dg * eCn) - k.cpTab * gate.dg * eCp;
    const T sj = k.cnTba * (p2 - gate.dg * eCn) - k.cpTba * gate.dg * eCp;
    const T ai = 2.0 * A * cpsi, bj = 2.0 * B * cpsi;
    const Xyz<T> rni = cross(r, ni);
    out.ti(
        Xyz<T>{si * nn.x + k.cpTab * ai * rni.x, si * nn.y + k.cpTab * ai * rni.y, si * nn.z + k.cpTab * ai * rni.z});
    const Xyz<T> rnj = cross(r, nj);
    out.tj(Xyz<T>{-sj * nn.x + k.cpTba * bj * rnj.x, -sj * nn.y + k.cpTba * bj * rnj.y,
                  -sj * nn.z + k.cpTba * bj * rnj.z});
    out.virial(k.cnE * cn * r2 + k.cpE * dot(r, cp));
    if constexpr (Energy) out.energy(k.cnE * d2 * psi + k.cpE * ab2 * cpsi);
}

// The same, its results in one OrientedForces (the reference's form).
template <bool Energy, class T>
[[gnu::always_inline]] inline OrientedForces<T> orientedPair(const Xyz<T>& r, T r2, T invR, const Xyz<T>& ni,
                                                             const Xyz<T>& nj, const Psi<T>& w, T c,
                                                             const OrientedWeights<T>& k) {
    struct Collect {
        OrientedForces<T> o{};
        void fj(const Xyz<T>& v) { o.fj = v; }
        void fi(const Xyz<T>& v) { o.fi = v; }
        void ti(const Xyz<T>& v) { o.ti = v; }
        void tj(const Xyz<T>& v) { o.tj = v; }
        void virial(T v) { o.virial = v; }
        void energy(T v) { o.energy = v; }
    } c2;
    orientedPair<Energy>(r, r2, invR, normalPair(r, ni, nj), w, c, k, c2);
    return c2.o;
}

}  // namespace bop::core
