// The pair loops over pruned copies of the neighbour list (PrunedPairs.hpp) against the same
// loops over the whole list: the same forces and torques to the bit while particles drift (and
// cross periodic faces), pruned again as they move, with fewer pairs to visit.
#include "core/ForceField.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace bop;
using namespace bop::core;

namespace {

// Species 1 surface, 2 and 3 volume; asymmetric weights; a periodic box 9 x 7.2 x 9.9 r0; an outer
// skin of 0.6 r0 (the pruned copies must be pruned again many times between two builds).
Model bag(double pruneR0) {
    Model m;
    m.species.assign(4, Species{});
    m.species[1].kind = ParticleKind::Surface;
    m.species[2].kind = m.species[3].kind = ParticleKind::Volume;
    m.lj = WeightMatrix(3, 1.0);
    m.lj(2, 3) = 0.6;
    m.lj(3, 2) = 1.4;
    m.coNormal = WeightMatrix(3, 0.3);
    m.coPlanar = WeightMatrix(3, 0.3);
    m.box.hi = Eigen::Vector3d(9.0, 7.2, 9.9) * kR0;
    m.box.periodic = {true, true, true};
    m.integration.skinR0 = 0.6;
    m.integration.pruneR0 = pruneR0;
    return m;
}

Particles scattered(const Model& m, std::size_t n) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    Particles p;
    while (p.size() < n) {
        const Eigen::Vector3d x = m.box.size().cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
        bool ok = true;
        for (const auto& y : p.pos) {
            Eigen::Vector3d r = x - y;
            for (int a = 0; a < 3; ++a) r[a] -= m.box.size()[a] * std::round(r[a] / m.box.size()[a]);
            ok = ok && r.norm() > 0.75 * kR0;
        }
        if (!ok) continue;
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        p.add(x, 1 + int(p.size() % 3), p.size() + 1, Eigen::Quaterniond(Eigen::AngleAxisd(3 * u(rng), axis)));
    }
    return p;
}

}  // namespace

TEST_CASE("pruned pair lists give the whole list's forces and torques to the bit as particles drift",
          "[core][neighbours][prune]") {
    const Model whole = bag(0.0), pruned = bag(0.05);
    Particles p = scattered(whole, 420);
    ForceField a(whole), b(pruned);
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0, 0.004 * kR0);  // per move
    const Eigen::Vector3d L = whole.box.size();
    std::size_t differing = 0, fewerLj = 0, fewerWide = 0, compared = 0;
    for (int it = 0; it < 80; ++it) {
        for (auto& x : p.pos) {
            x += Eigen::Vector3d(g(rng), g(rng), g(rng)) + Eigen::Vector3d(0.004, 0.0, -0.003) * kR0;
            for (int c = 0; c < 3; ++c) x[c] -= L[c] * std::floor((x[c] - whole.box.lo[c]) / L[c]);
        }
        Particles pa = p, pb = p;
        ForceStats sa, sb;
        a.compute(whole, ProbeState{}, pa, sa, nullptr, it % 4 == 0);
        b.compute(pruned, ProbeState{}, pb, sb, nullptr, it % 4 == 0);
        for (std::size_t i = 0; i < p.size(); ++i, ++compared)
            differing += pa.force[i] != pb.force[i] || pa.torque[i] != pb.torque[i];
        CHECK(sa.pairsInRange == sb.pairsInRange);
        CHECK(sa.orientedPairsInRange == sb.orientedPairsInRange);
        CHECK(sb.virial == Approx(sa.virial).epsilon(1e-13));
        CHECK(sb.pairEnergy == Approx(sa.pairEnergy).epsilon(1e-13));
        fewerLj += b.pruned().pairCount() < a.neighbours().pairCount();
        fewerWide += b.pruned().widePairCount() < a.neighbours().widePairCount();
    }
    INFO(a.neighbours().builds() << " list builds, " << b.pruned().prunes() << " prunings, last "
                                 << b.pruned().pairCount() << " of " << b.neighbours().pairCount() << " LJ pairs, "
                                 << b.pruned().widePairCount() << " of " << b.neighbours().widePairCount()
                                 << " oriented");
    CHECK(differing == 0);
    CHECK(compared == 80 * 420);
    CHECK(b.neighbours().builds() == a.neighbours().builds());
    CHECK(a.pruneSkin() == 0);
    CHECK(b.pruned().prunes() > b.neighbours().builds() + 3);  // pruned again between builds
    CHECK(b.pruned().prunes() < 60);                           // and reused in between
    CHECK(fewerLj == 80);
    CHECK(fewerWide == 80);
}
