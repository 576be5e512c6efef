// Mixed precision (Integration::mixedPrecision, the pair loops in float lanes with double sums)
// against double: the forces agree to 1e-5 of their size on bulk material and on a mix of
// species with asymmetric weights, the LJ energies (double in both) agree, the oriented loop's
// forces and torques agree on surface particles (one set of weights and several), an undamped box
// drifts no more than twice as much, and a mixed run is the same to the last bit at 1, 2 and 3
// threads. Whole bags of the shipped scenes: tests/physics/TestMixedScenes.cpp.
#include "core/FccLattice.hpp"
#include "core/Integrator.hpp"
#include "core/Simulation.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace bop;
using namespace bop::core;

namespace {

// An fcc box of cells^3 cells at nearest distance r0, every site moved by up to 0.05 r0 per
// axis, periodic (scripts/bench/step.sh's workload). One volume species, or with `species3`
// the sites dealt among species 1..3 with asymmetric LJ weights (the loop's table path).
struct FccBox {
    std::shared_ptr<Model> model;
    Particles particles;
    Params params{1};
};

FccBox fccBox(int cells, bool species3, bool mixed, std::uint32_t seed) {
    FccBox b;
    b.model = std::make_shared<Model>();
    const int ns = species3 ? 3 : 1;
    b.model->species.assign(std::size_t(ns) + 1, Species{});
    for (int s = 1; s <= ns; ++s) b.model->species[std::size_t(s)].kind = ParticleKind::Volume;
    const double a = std::sqrt(2.0) * kR0;
    b.model->box.hi = Eigen::Vector3d::Constant(cells * a);
    b.model->box.periodic = {true, true, true};
    b.model->integration.dt = 0.005;
    b.model->integration.mixedPrecision = mixed;
    b.params = Params(ns);
    for (auto& d : b.params.drag) d = Drag{0.0, 0.0};
    if (species3) {
        b.params.lj(1, 2) = 0.5;
        b.params.lj(2, 1) = 1.5;
        b.params.lj(3, 1) = 0.8;
    }
    std::uint64_t id = 0;
    for (const Eigen::Vector3d& x : test::jitteredFcc(cells, seed)) {
        b.particles.add(x, species3 ? 1 + int(id % 3) : 1, id + 1);
        ++id;
    }
    return b;
}

Simulation simulationOf(const FccBox& b) {
    return Simulation(b.model, b.particles, {.params = b.params});
}

// |F_mixed - F_double| over |F_double|, over every particle's force together.
double forceDifference(const Particles& mixed, const Particles& dbl) {
    double d2 = 0, f2 = 0;
    for (std::size_t i = 0; i < dbl.size(); ++i) {
        d2 += (mixed.force[i] - dbl.force[i]).squaredNorm();
        f2 += dbl.force[i].squaredNorm();
    }
    return std::sqrt(d2 / f2);
}

// |T_mixed - T_double| over |T_double|, the torques alike.
double torqueDifference(const Particles& mixed, const Particles& dbl) {
    double d2 = 0, t2 = 0;
    for (std::size_t i = 0; i < dbl.size(); ++i) {
        d2 += (mixed.torque[i] - dbl.torque[i]).squaredNorm();
        t2 += dbl.torque[i].squaredNorm();
    }
    return std::sqrt(d2 / t2);
}

// Surface particles of species 1 and 2 and volume particles of species 3, randomly oriented, at
// least 0.85 r0 apart in a closed box of 9 r0; co-normal and co-planar weights 0.3 between the
// surfaces, or with `asymmetric` 0.5 from 1 to 2 and 0.2 from 2 to 1 (the loop's per-lane weights).
FccBox orientedCloud(bool asymmetric, bool mixed) {
    FccBox b;
    b.model = std::make_shared<Model>();
    b.model->species.assign(4, Species{});
    b.model->species[1].kind = b.model->species[2].kind = ParticleKind::Surface;
    b.model->species[3].kind = ParticleKind::Volume;
    b.model->box.hi = Eigen::Vector3d::Constant(9 * kR0);
    b.model->integration.dt = 0.005;
    b.model->integration.mixedPrecision = mixed;
    b.params = Params(3);
    for (auto& d : b.params.drag) d = Drag{0.0, 0.0};
    b.params.coNormal = b.params.coPlanar = WeightMatrix(3, 0.0);
    for (int a : {1, 2})
        for (int c : {1, 2}) b.params.coNormal(a, c) = b.params.coPlanar(a, c) = 0.3;
    if (asymmetric) {
        b.params.coNormal(1, 2) = b.params.coPlanar(1, 2) = 0.5;
        b.params.coNormal(2, 1) = b.params.coPlanar(2, 1) = 0.2;
    }
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(0, 1);
    for (int tries = 0; b.particles.size() < 700 && tries < 100000; ++tries) {
        const Eigen::Vector3d x = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 9 * kR0;
        bool ok = true;
        for (const auto& y : b.particles.pos) ok = ok && (x - y).norm() > 0.85 * kR0;
        if (!ok) continue;
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        b.particles.add(x, 1 + int(b.particles.size() % 3), b.particles.size() + 1,
                        Eigen::Quaterniond(Eigen::AngleAxisd(3 * u(rng), axis)));
    }
    return b;
}

}  // namespace

TEST_CASE("mixed precision: the oriented loop's forces and torques are double's to 1e-5", "[core][mixed]") {
    for (const bool asymmetric : {false, true}) {
        const FccBox d = orientedCloud(asymmetric, false), m = orientedCloud(asymmetric, true);
        REQUIRE(d.particles.size() == 700);
        Simulation sd = simulationOf(d), sm = simulationOf(m);
        sd.refreshForces();
        sm.refreshForces();
        const ForceStats& fd = sd.stats().forces;
        const ForceStats& fm = sm.stats().forces;
        const double df = forceDifference(sm.particles(), sd.particles());
        const double dt = torqueDifference(sm.particles(), sd.particles());
        INFO((asymmetric ? "asymmetric" : "one set of")
             << " weights: force difference " << df << ", torque " << dt << ", oriented pairs "
             << fd.orientedPairsInRange << " / " << fm.orientedPairsInRange << ", energies " << fd.pairEnergy << " / "
             << fm.pairEnergy);
        CHECK(fd.orientedPairsInRange > 5000);
        CHECK(fm.orientedPairsInRange == fd.orientedPairsInRange);
        CHECK(df < 1e-5);
        CHECK(dt < 1e-5);
        CHECK(dt > 0);  // float arithmetic in the oriented loop too
        CHECK(std::abs(fm.pairEnergy - fd.pairEnergy) <= 1e-5 * std::abs(fd.pairEnergy));
        CHECK(std::abs(fm.virial - fd.virial) <= 1e-5 * std::abs(fd.virial));
    }
}

TEST_CASE("mixed precision: the forces are double's to 1e-5, the energies and virial alike", "[core][mixed]") {
    for (const bool species3 : {false, true}) {
        const FccBox d = fccBox(8, species3, false, 5), m = fccBox(8, species3, true, 5);
        Simulation sd = simulationOf(d), sm = simulationOf(m);
        sd.refreshForces();
        sm.refreshForces();
        const ForceStats& fd = sd.stats().forces;
        const ForceStats& fm = sm.stats().forces;
        const double diff = forceDifference(sm.particles(), sd.particles());
        INFO((species3 ? "three species" : "one species")
             << ": force difference " << diff << ", pair energies " << fd.pairEnergy << " / " << fm.pairEnergy
             << ", virial " << fd.virial << " / " << fm.virial);
        CHECK(fm.pairsInRange == fd.pairsInRange);
        CHECK(diff < 1e-5);
        CHECK(diff > 0);  // float arithmetic, not double's by another name
        CHECK(std::abs(fm.pairEnergy - fd.pairEnergy) <= 1e-9 * std::abs(fd.pairEnergy));
        CHECK(std::abs(fm.virial - fd.virial) <= 1e-5 * std::abs(fd.virial));
    }
}

TEST_CASE("mixed precision: an undamped box drifts no more than twice as much as in double", "[core][mixed]") {
    double drift[2] = {0, 0};
    for (const bool mixed : {false, true}) {
        const FccBox b = fccBox(6, false, mixed, 9);
        Simulation sim = simulationOf(b);
        sim.refreshForces();
        const double e0 = sim.stats().forces.pairEnergy + kineticEnergy(*b.model, sim.particles());
        for (int s = 0; s < 20; ++s) {
            sim.run(100);
            sim.refreshForces();
            drift[mixed] = std::max(drift[mixed], std::abs(sim.stats().total() - e0) / std::abs(e0));
        }
    }
    INFO("largest |E - E0| / |E0| over 2,000 steps: double " << drift[0] << ", mixed " << drift[1]);
    CHECK(drift[0] < 1e-4);
    CHECK(drift[1] <= 2 * drift[0] + 1e-7);
}

TEST_CASE("mixed precision: a run is the same to the last bit at 1, 2 and 3 threads", "[core][mixed][threads]") {
    const int before = threadCount();
    for (const FccBox& b : {fccBox(8, true, true, 3), orientedCloud(true, true)}) {
        std::vector<Particles> ends;
        for (int threads : {1, 2, 3}) {
            setThreadCount(threads);
            Simulation sim = simulationOf(b);
            sim.run(200);
            ends.push_back(sim.particles());
        }
        for (std::size_t k = 1; k < ends.size(); ++k) {
            CHECK(ends[k].pos == ends[0].pos);
            CHECK(ends[k].vel == ends[0].vel);
            bool sameOrientations = ends[k].q.size() == ends[0].q.size();
            for (std::size_t i = 0; sameOrientations && i < ends[0].q.size(); ++i)
                sameOrientations = ends[k].q[i].coeffs() == ends[0].q[i].coeffs();
            CHECK(sameOrientations);
        }
        double moved = 0;
        for (std::size_t i = 0; i < b.particles.size(); ++i)
            moved = std::max(moved, (ends[0].pos[i] - b.particles.pos[i]).norm());
        CHECK(moved > 0.01);
    }
    setThreadCount(before);
}
