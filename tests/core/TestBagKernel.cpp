// The step's pair loops (LJ list, oriented list, chunks on threads) against the O(N^2) reference
// on a curved bag: two surface species and a volume species, asymmetric weights, and the map's
// curvature weights on the co-planar terms, which vary along an ellipsoid's surface.
#include "BruteForce.hpp"
#include "core/TargetClones.hpp"
#include "shape/ShapeTestUtil.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <string>

using namespace bop;
using namespace bop::core;

namespace {

// The loops (in whichever clone this CPU runs) against the reference on the ellipsoid bag.
// uniformLj: every species pair with the same LJ weights (the loop's path without look-ups),
// else asymmetric ones.
void checkBagAgainstReference(bool uniformLj = false) {
    const Dims d{34, 26, 22};
    auto map = std::make_shared<GradientMap>(test::mapFrom(test::depthFrom(
        d, {[](const Eigen::Vector3d& x) {
            const Eigen::Vector3d u = (x - Eigen::Vector3d(17.2, 12.9, 11.1)).cwiseQuotient(Eigen::Vector3d(13, 9, 7));
            return u.squaredNorm() < 1.0;
        }})));
    auto m = std::make_shared<Model>();
    m->species.assign(4, Species{});
    m->species[1].kind = m->species[3].kind = ParticleKind::Surface;
    for (auto& s : m->species) s.alphaForceGm = s.alphaTorqueGm = 0;  // the pairs alone
    Params w(3);
    w.coNormal = WeightMatrix(3, 0.3);
    w.coPlanar = WeightMatrix(3, 0.3);
    if (!uniformLj) {
        w.lj(1, 2) = 0.5;
        w.lj(2, 1) = 1.5;
        m->species[3].alphaForceOp = 0.8;
    }
    w.coNormal(1, 3) = 0.1;
    w.coPlanar(3, 1) = 0.7;
    w.coPlanar(3, 3) = 0.0;  // a surface pair with co-normal weight only
    m->species[1].alphaTorqueOp = 1.3;
    REQUIRE(PairKernel(*m, w, false).ljUniform() == uniformLj);
    m->map = map;
    m->curvatureWeighting = true;
    const double h = voxelLength(map->r0Voxels);
    m->box.hi = Eigen::Vector3d(d.nx, d.ny, d.nz) * h;

    std::mt19937 rng(21);
    std::uniform_real_distribution<double> u(0, 1);
    Particles p;
    while (p.size() < 900) {
        const Eigen::Vector3d x = m->box.hi.cwiseProduct(Eigen::Vector3d(u(rng), u(rng), u(rng)));
        bool ok = true;
        for (const auto& y : p.pos) ok = ok && (x - y).norm() > 0.6 * kR0;
        if (!ok) continue;
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        p.add(x, 1 + int(p.size() % 3), p.size() + 1, Eigen::Quaterniond(Eigen::AngleAxisd(u(rng) * 3.0, axis)));
    }
    float wLo = 1e9f, wHi = -1e9f;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (m->isSurface(p.species[i])) {
            const float w = MapForces::curvatureWeight(*m, m->map.get(), p.pos[i], p.species[i]);
            wLo = std::min(wLo, w), wHi = std::max(wHi, w);
        }
    ForceField field(*m, w, m->map != nullptr);
    const test::BruteForceComparison c = test::compareWithBruteForce(*m, w, field, p);
    const ForceStats &a = c.field, &b = c.brute;
    const double maxF = c.maxForce, errF = c.forceError, errT = c.torqueError;
    INFO("curvature weights " << wLo << " to " << wHi << "; LJ pairs " << a.pairsInRange << ", oriented "
                              << a.orientedPairsInRange << "; max |F| " << maxF << ", errors " << errF << ", " << errT);
    CHECK(wHi - wLo > 0.05);  // the weights differ from pair to pair
    CHECK(a.pairsInRange == b.pairsInRange);
    CHECK(a.orientedPairsInRange == b.orientedPairsInRange);
    CHECK(a.orientedPairsInRange > 1000);
    CHECK(errF < 1e-12 * maxF);
    CHECK(errT < 1e-12 * maxF);
    CHECK(a.pairEnergy == Approx(b.pairEnergy).epsilon(1e-12));
    CHECK(a.virial == Approx(b.virial).epsilon(1e-12));
}

}  // namespace

TEST_CASE("the bag's pair loops equal the O(N^2) reference with curvature weights and asymmetric species",
          "[core][cells][curvature]") {
    INFO("pair loops: " << hotLoopClone() << " clone");
    checkBagAgainstReference();
}

TEST_CASE("with the same LJ weights for every species pair the loop takes them once and equals the reference",
          "[core][cells][curvature]") {
    checkBagAgainstReference(true);
}

// The AVX-512 clone (TargetClones.hpp) is the one the loader picks on a CPU that has x86-64-v4; there
// it must agree with the reference as the others do.
TEST_CASE("the x86-64-v4 (AVX-512) clone equals the O(N^2) reference where the CPU has it", "[core][cells][clones]") {
    if (std::string(hotLoopClone()) != "x86-64-v4") {
        WARN("skipped: this CPU or build runs the " << hotLoopClone() << " clone, not x86-64-v4 (AVX-512)");
        return;
    }
#if BOP_HOT_LOOP_CLONES
    __builtin_cpu_init();
    REQUIRE(__builtin_cpu_supports("avx512f"));
    REQUIRE(__builtin_cpu_supports("avx512vl"));
#endif
    checkBagAgainstReference();
    checkBagAgainstReference(true);
}
