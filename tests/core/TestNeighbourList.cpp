// The Verlet neighbour list: every pair within range exactly once (ghost images across
// periodic faces included), forces equal to brute force while particles move, cross periodic
// faces, appear and disappear, and the LJ-only fast path against the general one.
#include "core/ForceField.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace bop;
using namespace bop::core;

namespace {

std::vector<Eigen::Vector3d> randomPoints(const Box& box, int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i)
        pts.push_back(box.lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.size()));
    return pts;
}

Eigen::Vector3d minimumImage(const Box& box, Eigen::Vector3d r) {
    for (int a = 0; a < 3; ++a)
        if (box.periodic[std::size_t(a)]) r[a] -= box.size()[a] * std::round(r[a] / box.size()[a]);
    return r;
}

// Species 1 surface, 2 and 3 volume (volume-only when surface = false: species 1 is volume too).
std::shared_ptr<Model> model(bool surface, bool periodic, double boxR0) {
    auto m = std::make_shared<Model>();
    m->species.assign(4, Species{});
    for (int s = 1; s <= 3; ++s) m->species[std::size_t(s)].kind = ParticleKind::Volume;
    if (surface) m->species[1].kind = ParticleKind::Surface;
    m->lj = WeightMatrix(3, 1.0);
    m->lj(2, 3) = 0.6;  // asymmetric: alpha_23 to 2, alpha_32 to 3
    m->lj(3, 2) = 1.4;
    m->species[3].alphaForceOp = 0.8;
    m->coNormal = WeightMatrix(3, surface ? 0.3 : 0.0);
    m->coPlanar = WeightMatrix(3, surface ? 0.3 : 0.0);
    m->box.hi = Eigen::Vector3d(boxR0, 0.8 * boxR0, 1.1 * boxR0) * kR0;
    m->box.periodic = {periodic, periodic, periodic};
    return m;
}

Particles particles(const Model& m, int n, std::uint32_t seed) {
    Particles p;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const auto& x : randomPoints(m.box, 4 * n, seed)) {
        bool ok = true;
        for (const auto& y : p.pos) ok = ok && minimumImage(m.box, x - y).norm() > 0.75 * kR0;
        if (!ok) continue;
        const Eigen::Quaterniond q(Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
        p.add(x, 1 + int(p.size() % 3), p.size() + 1, q);
        if (int(p.size()) == n) break;
    }
    return p;
}

// Largest difference between the field's forces and torques and brute force, relative to the
// largest brute-force force.
double bruteForceError(const Model& m, ForceField& field, Particles& p, bool energies) {
    ForceStats a, b;
    field.compute(m, ProbeState{}, p, a, nullptr, energies);
    Particles q = p;
    for (std::size_t i = 0; i < q.size(); ++i) { q.force[i].setZero(); q.torque[i].setZero(); }
    ForceField::computePairsBruteForce(m, q, b);
    REQUIRE(a.pairsInRange == b.pairsInRange);
    CHECK(a.virial == Approx(b.virial).epsilon(1e-11));
    double maxF = 1, err = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        maxF = std::max(maxF, q.force[i].norm());
        err = std::max({err, (p.force[i] - q.force[i]).norm(), (p.torque[i] - q.torque[i]).norm()});
    }
    return err / maxF;
}

}  // namespace

TEST_CASE("the neighbour list holds every pair within range exactly once", "[core][neighbours]") {
    for (bool periodic : {true, false}) {
        Box box;
        box.lo = Eigen::Vector3d(-3, 1, 2);
        box.hi = box.lo + Eigen::Vector3d(14, 11, 17);
        box.periodic = {periodic, periodic, periodic};
        const double range = 3.3;
        const auto pts = randomPoints(box, 900, periodic ? 7 : 8);
        NeighbourList list;
        list.build(box, range, pts);
        REQUIRE(list.update(box, pts, 0.1));
        std::set<std::pair<std::uint32_t, std::uint32_t>> found;
        std::size_t duplicates = 0;
        for (std::size_t e = 0; e < list.entryCount(); ++e)
            for (std::uint32_t k = list.first(e); k < list.first(e + 1); ++k) {
                const std::uint32_t i = list.owner()[e], j = list.owner()[list.neighbours()[k]];
                duplicates += !found.insert({std::min(i, j), std::max(i, j)}).second;
            }
        std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
        for (std::uint32_t i = 0; i < pts.size(); ++i)
            for (std::uint32_t j = i + 1; j < pts.size(); ++j)
                if (minimumImage(box, pts[j] - pts[i]).norm() < range) expected.insert({i, j});
        INFO("periodic " << periodic << ": " << expected.size() << " pairs, " << list.ghostCount() << " ghosts");
        CHECK(duplicates == 0);
        CHECK(found == expected);
        CHECK(expected.size() > 5000);
        CHECK((list.ghostCount() > 0) == periodic);
    }
}

TEST_CASE("a periodic box narrower than twice the neighbour range is refused", "[core][neighbours]") {
    Box box;
    box.hi = Eigen::Vector3d(10, 6, 10);
    box.periodic = {true, true, true};
    NeighbourList list;
    CHECK_THROWS_WITH(list.build(box, 3.3, randomPoints(box, 10, 1)), Catch::Contains("twice the neighbour range"));
}

TEST_CASE("forces match brute force as particles drift across periodic faces and are replaced", "[core][neighbours]") {
    for (bool surface : {true, false}) {
        for (bool periodic : {true, false}) {
            auto m = model(surface, periodic, 9.0);
            Particles p = particles(*m, 320, periodic ? 3 : 4);
            ForceField field(*m);
            std::mt19937 rng(11);
            std::normal_distribution<double> g(0, 0.01 * kR0);  // per move, well below skin / 2
            const Eigen::Vector3d L = m->box.size();
            double worst = 0;
            int wraps = 0;
            for (int it = 0; it < 60; ++it) {
                for (auto& x : p.pos) {
                    x += Eigen::Vector3d(g(rng), g(rng), g(rng)) + Eigen::Vector3d(0.02, 0.015, 0.0) * kR0;
                    for (int a = 0; a < 3 && periodic; ++a)
                        if (x[a] < m->box.lo[a] || x[a] >= m->box.hi[a]) {
                            x[a] -= L[a] * std::floor((x[a] - m->box.lo[a]) / L[a]);
                            ++wraps;
                        }
                }
                if (it == 20) {  // a death and a birth in one step: same count, other particles
                    std::vector<char> die(p.size(), 0);
                    die[5] = 1;
                    p.removeIf(die);
                    p.add(m->box.lo + 0.5 * L, 2, 10000);
                }
                worst = std::max(worst, bruteForceError(*m, field, p, it % 3 == 0));
            }
            INFO("surface " << surface << ", periodic " << periodic << ": " << field.neighbours().builds()
                            << " list builds, " << wraps << " wraps");
            CHECK(worst < 1e-12);
            CHECK(field.neighbours().builds() > 2);   // rebuilt as particles drift and after the birth
            CHECK(field.neighbours().builds() < 40);  // and reused in between
            CHECK((wraps > 0) == periodic);
        }
    }
}
