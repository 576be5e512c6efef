#pragma once
// The work for one pair (i, j) with r = p_j - p_i: LJ for every pair, co-normal and co-planar
// for two surface particles; weights alpha_ab to i and alpha_ba to j (paper eqs. 6-8) combined
// with each species' alpha_f^OP and alpha_tau^OP (eqs. 2-3) into one table per potential.
// apply() is the reference, pair by pair with energies (the O(N^2) check); the step's loops
// (LjPairLoop, OrientedPairLoop) read the same tables and evaluate the same physics
// (LjForm::forceOverR, OrientedTerms.hpp).
#include "Model.hpp"
#include "Params.hpp"
#include "Potentials.hpp"

#include <vector>

namespace bop::core {

class PairKernel {
public:
    // The scene's species and potentials, the weights in force; `map`: the run has a gradient map
    // (whose curvature weights the co-planar terms read, when the scene weights by curvature).
    PairKernel(const Model& m, const Params& p, bool map)
        : lj_(m.ljParams), weight_(m.oriented), n_(m.speciesCount() + 1), useCurvature_(m.curvatureWeighting && map) {
        const std::size_t nn = std::size_t(n_) * n_;
        ljF_.assign(nn, 0);
        ljE_.assign(nn, 0);
        cnF_.assign(nn, 0);
        cnT_.assign(nn, 0);
        cpF_.assign(nn, 0);
        cpT_.assign(nn, 0);
        cnE_.assign(nn, 0);
        cpE_.assign(nn, 0);
        oriented_.assign(nn, 0);
        for (int a = 1; a < n_; ++a)
            for (int b = 1; b < n_; ++b) {
                const std::size_t k = std::size_t(a) * n_ + b;
                const Species& sa = m.species[std::size_t(a)];
                ljF_[k] = sa.alphaForceOp * p.lj(a, b);
                ljE_[k] = 0.5 * (p.lj(a, b) + p.lj(b, a));
                const bool both = m.isSurface(a) && m.isSurface(b);
                if (!both) continue;
                cnF_[k] = sa.alphaForceOp * p.coNormal(a, b);
                cnT_[k] = sa.alphaTorqueOp * p.coNormal(a, b);
                cpF_[k] = sa.alphaForceOp * p.coPlanar(a, b);
                cpT_[k] = sa.alphaTorqueOp * p.coPlanar(a, b);
                cnE_[k] = 0.5 * (p.coNormal(a, b) + p.coNormal(b, a));
                cpE_[k] = 0.5 * (p.coPlanar(a, b) + p.coPlanar(b, a));
                oriented_[k] =
                    (p.coNormal(a, b) != 0 || p.coNormal(b, a) != 0 || p.coPlanar(a, b) != 0 || p.coPlanar(b, a) != 0);
            }
        cutoff2_ = std::max(lj_.cutoff2(), m.hasSurfaceSpecies() ? weight_.cutoff2() : 0.0);
        for (int a = 1; a < n_; ++a)
            for (int b = 1; b < n_; ++b) {
                const std::size_t k = std::size_t(a) * n_ + b, first = std::size_t(n_) + 1;
                ljUniform_ = ljUniform_ && ljF_[k] == ljF_[first] && ljE_[k] == ljE_[first];
            }
        uniformOriented_ = findUniformOrientedPair();
        ljF32_.assign(ljF_.begin(), ljF_.end());
        ljE32_.assign(ljE_.begin(), ljE_.end());
        for (const auto* t : {&cnF_, &cnT_, &cpF_, &cpT_, &cnE_, &cpE_}) oriented32_.emplace_back(t->begin(), t->end());
    }

    const LjForm& lj() const { return lj_; }
    int tableSide() const { return n_; }  // species tables are tableSide() x tableSide(), row a, column b
    const double* ljForceWeights() const { return ljF_.data(); }   // alpha_f^OP(a) * alpha_ab
    const double* ljEnergyWeights() const { return ljE_.data(); }  // (alpha_ab + alpha_ba) / 2
    // The same rounded to float, for the mixed-precision loop (PairInputs::mixed).
    const float* ljForceWeights32() const { return ljF32_.data(); }
    const float* ljEnergyWeights32() const { return ljE32_.data(); }
    // Every species pair has the same LJ weights (a bag's surface and volume at the defaults):
    // the loop may take pair (1, 1)'s for all, the same numbers without the look-ups.
    bool ljUniform() const { return ljUniform_; }
    bool anyOriented() const {
        for (char o : oriented_)
            if (o) return true;
        return false;
    }
    double cutoff2() const { return cutoff2_; }
    const OrientedWeight& weight() const { return weight_; }
    bool curvature() const { return useCurvature_; }  // co-planar terms weighted by the map's curvature
    // Whether species s has co-normal or co-planar weights with some species (either way).
    bool orientedSpecies(int s) const {
        for (int b = 1; b < n_; ++b)
            if (oriented_[std::size_t(s) * n_ + b] || oriented_[std::size_t(b) * n_ + s]) return true;
        return false;
    }
    // The one species with oriented weights when there is exactly one (a bag's surface), else 0.
    int singleOrientedSpecies() const {
        int found = 0;
        for (int s = 1; s < n_; ++s)
            if (orientedSpecies(s)) {
                if (found) return 0;
                found = s;
            }
        return found;
    }
    // The index a * tableSide() + b of a species pair whose oriented weights every pair with
    // oriented weights shares (several bags' surfaces at one set of parameters), else -1.
    int uniformOrientedPair() const { return uniformOriented_; }

private:
    int findUniformOrientedPair() const {
        int found = -1;
        for (int k = 0; k < n_ * n_; ++k) {
            if (!oriented_[std::size_t(k)]) continue;
            if (found < 0) {
                found = k;
                continue;
            }
            const std::size_t a = std::size_t(found), b = std::size_t(k);
            if (cnF_[a] != cnF_[b] || cnT_[a] != cnT_[b] || cpF_[a] != cpF_[b] || cpT_[a] != cpT_[b] ||
                cnE_[a] != cnE_[b] || cpE_[a] != cpE_[b])
                return -1;
        }
        return found;
    }

public:
    // The oriented terms' tables, tableSide() x tableSide(), row a, column b.
    struct OrientedTables {
        const double *cnF, *cnT, *cpF, *cpT, *cnE, *cpE;  // as the LJ tables, per term and kind
        const char* on;                                   // the pair has some oriented weight
    };
    OrientedTables orientedTables() const {
        return {cnF_.data(), cnT_.data(), cpF_.data(), cpT_.data(), cnE_.data(), cpE_.data(), oriented_.data()};
    }
    // The same rounded to float, for the mixed-precision oriented loop.
    struct OrientedTables32 {
        const float *cnF, *cnT, *cpF, *cpT, *cnE, *cpE;
        const char* on;
    };
    OrientedTables32 orientedTables32() const {
        const auto& t = oriented32_;
        return {t[0].data(), t[1].data(), t[2].data(), t[3].data(), t[4].data(), t[5].data(), oriented_.data()};
    }

    struct Sums {
        double energy = 0, virial = 0, virialVolume = 0;
        std::size_t inRange = 0;          // pairs within the LJ cutoff
        std::size_t orientedInRange = 0;  // pairs with oriented weights within their cutoff
    };

    // The LJ part of apply() alone (the whole of it for models without oriented weights).
    inline void applyLj(std::size_t i, std::size_t j, int a, int b, const Eigen::Vector3d& r, double r2,
                        Eigen::Vector3d* f, bool volumeA, bool volumeB, Sums& s) const {
        const std::size_t ab = std::size_t(a) * n_ + b, ba = std::size_t(b) * n_ + a;
        double fOverR, e = 0;
        if (lj_.eval(r2, fOverR, e)) {
            ++s.inRange;
            const Eigen::Vector3d fj = fOverR * r;
            f[j] += ljF_[ba] * fj;
            f[i] -= ljF_[ab] * fj;
            s.energy += ljE_[ab] * e;
            const double w = ljE_[ab] * fOverR * r2;
            s.virial += w;
            if (volumeA && volumeB) s.virialVolume += w;
        }
    }

    // Accumulates the pair's forces and torques into f[i], f[j], t[i], t[j].
    // wi, wj: curvature weights of the co-planar term (1 without a map).
    inline void apply(std::size_t i, std::size_t j, int a, int b, const Eigen::Vector3d& r, double r2,
                      const Eigen::Vector3d& ni, const Eigen::Vector3d& nj, float wi, float wj, Eigen::Vector3d* f,
                      Eigen::Vector3d* t, bool volumeA, bool volumeB, Sums& s) const {
        if (r2 >= cutoff2_) return;
        applyLj(i, j, a, b, r, r2, f, volumeA, volumeB, s);
        const std::size_t ab = std::size_t(a) * n_ + b, ba = std::size_t(b) * n_ + a;
        if (!oriented_[ab] || r2 >= weight_.cutoff2()) return;
        const double rlen = std::sqrt(r2);
        double psi, dpsi;
        if (!weight_.eval(rlen, psi, dpsi)) return;
        ++s.orientedInRange;
        const OrientedWeights<double> k{cnF_[ab], cnF_[ba], cnT_[ab], cnT_[ba], cnE_[ab],
                                        cpF_[ab], cpF_[ba], cpT_[ab], cpT_[ba], cpE_[ab]};
        const double c = useCurvature_ ? 0.5 * (double(wi) + double(wj)) : 1.0;
        const OrientedForces<double> o =
            orientedPair<true>(xyzOf(r), r2, inverseOrZero(rlen), xyzOf(ni), xyzOf(nj), {psi, dpsi}, c, k);
        f[j] += vectorOf(o.fj);
        f[i] += vectorOf(o.fi);
        t[i] += vectorOf(o.ti);
        t[j] += vectorOf(o.tj);
        s.energy += o.energy;
        s.virial += o.virial;
    }

private:
    LjForm lj_;
    OrientedWeight weight_;
    int n_;
    bool useCurvature_;
    bool ljUniform_ = true;
    int uniformOriented_ = -1;  // uniformOrientedPair()
    double cutoff2_ = 0;
    std::vector<double> ljF_, ljE_, cnF_, cnT_, cpF_, cpT_, cnE_, cpE_;
    std::vector<float> ljF32_, ljE32_;
    std::vector<std::vector<float>> oriented32_;  // cnF_, cnT_, cpF_, cpT_, cnE_, cpE_ in float
    std::vector<char> oriented_;
};

}  // namespace bop::core
