// The dynamics core without a shape: cell lists against brute force, momentum conservation,
// energy conservation of an undamped LJ cluster, exact drag and rotation, and deterministic runs.
#include "BruteForce.hpp"
#include "core/BloodPressure.hpp"
#include "core/Integrator.hpp"
#include "core/Simulation.hpp"
#include "core/SoundState.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <limits>
#include <random>

using namespace bop;
using namespace bop::core;

namespace {

// Species 1 surface, 2 volume, 3 surface; asymmetric weights unless `symmetric`.
std::shared_ptr<Model> mixedModel(bool symmetric, bool damped, bool periodic, double boxR0) {
    auto m = std::make_shared<Model>();
    m->species.assign(4, Species{});
    m->species[1].kind = m->species[3].kind = ParticleKind::Surface;
    m->species[2].kind = ParticleKind::Volume;
    (void)damped;  // mixedParams' drags
    if (!symmetric) {
        m->species[3].alphaForceOp = 0.8;
        m->species[1].alphaTorqueOp = 1.3;
    }
    m->box.hi = Eigen::Vector3d::Constant(boxR0 * kR0);
    m->box.periodic = {periodic, periodic, periodic};
    return m;
}

// mixedModel's weights and drags.
Params mixedParams(bool symmetric, bool damped) {
    Params p(3);
    for (auto& d : p.drag) d = damped ? Drag{1.0, 0.3} : Drag{0.0, 0.0};
    p.coNormal = WeightMatrix(3, 0.3);
    p.coPlanar = WeightMatrix(3, 0.3);
    if (!symmetric) {
        p.lj(1, 2) = 0.5;
        p.lj(2, 1) = 1.5;
        p.coNormal(1, 3) = 0.1;
        p.coPlanar(3, 1) = 0.7;
    }
    return p;
}

Particles randomParticles(const Model& m, int n, double minDistR0, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    Particles p;
    const Eigen::Vector3d L = m.box.size();
    while (int(p.size()) < n) {
        const Eigen::Vector3d x(u(rng) * L.x(), u(rng) * L.y(), u(rng) * L.z());
        bool ok = true;
        for (const auto& y : p.pos) ok = ok && (x - y).norm() > minDistR0 * kR0;
        if (!ok) continue;
        const int s = 1 + int(p.size() % 3);
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        p.add(x, s, p.size() + 1, Eigen::Quaterniond(Eigen::AngleAxisd(u(rng) * 3.0, axis)));
    }
    return p;
}

Eigen::Vector3d momentum(const Particles& p) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (const auto& v : p.vel) s += v;
    return s;
}

}  // namespace

TEST_CASE("cell-list forces and torques equal O(N^2) brute force", "[core][cells]") {
    for (bool periodic : {false, true}) {
        auto m = mixedModel(false, false, periodic, 10.0);
        Particles p = randomParticles(*m, 300, 0.6, periodic ? 2 : 1);
        ForceField field(*m, mixedParams(false, false), m->map != nullptr);
        const test::BruteForceComparison c = test::compareWithBruteForce(*m, mixedParams(false, false), field, p);
        const ForceStats &a = c.field, &b = c.brute;
        const double maxF = c.maxForce, errF = c.forceError, errT = c.torqueError;
        INFO("periodic " << periodic << ": LJ pairs in range " << a.pairsInRange << ", oriented "
                         << a.orientedPairsInRange << ", max |F| " << maxF);
        CHECK(a.pairsInRange == b.pairsInRange);
        CHECK(a.orientedPairsInRange == b.orientedPairsInRange);
        CHECK(a.pairsInRange > 500);
        CHECK(a.orientedPairsInRange > 1000);
        CHECK(errF < 1e-12 * std::max(1.0, maxF));
        CHECK(errT < 1e-12 * std::max(1.0, maxF));
        CHECK(a.pairEnergy == Approx(b.pairEnergy).epsilon(1e-12));
        CHECK(a.virial == Approx(b.virial).epsilon(1e-12));
    }
}

TEST_CASE("total momentum is conserved with symmetric weights and no field", "[core][conservation]") {
    auto m = mixedModel(true, false, false, 12.0);
    Particles p = randomParticles(*m, 200, 0.8, 3);
    std::mt19937 rng(4);
    std::normal_distribution<double> g(0, 0.2);
    double speed = 0;
    for (auto& v : p.vel) {
        v = Eigen::Vector3d(g(rng), g(rng), g(rng));
        speed += v.norm();
    }
    const Eigen::Vector3d p0 = momentum(p);
    Simulation sim(m, p, {.construction = Construction({}, {}, 3), .params = mixedParams(true, false)});
    sim.run(500);
    const double drift = (momentum(sim.particles()) - p0).norm() / speed;
    INFO("relative momentum change " << drift);
    CHECK(drift < 1e-10);
    // Asymmetric weights break it (the paper accepts this): the test can tell the difference.
    auto a = mixedModel(false, false, false, 12.0);
    Simulation asym(a, p, {.construction = Construction({}, {}, 3), .params = mixedParams(false, false)});
    asym.run(500);
    CHECK((momentum(asym.particles()) - p0).norm() / speed > 1e-6);
}

TEST_CASE("an undamped LJ cluster conserves energy over 10,000 steps", "[core][conservation]") {
    auto m = std::make_shared<Model>();
    m->species.assign(2, Species{});
    m->integration.dt = 0.02;
    m->box.hi = Eigen::Vector3d::Constant(20 * kR0);
    Particles p;
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 0.05);
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const std::size_t n = p.add(Eigen::Vector3d(8 + i, 8 + j, 8 + k) * kR0 * 1.02 +
                                                Eigen::Vector3d(0.5 * (j % 2), 0.5 * (k % 2), 0) * kR0,
                                            1, p.size() + 1);
                p.vel[n] = Eigen::Vector3d(g(rng), g(rng), g(rng));
            }
    Params undamped(1);
    undamped.drag[1].v = 0;
    Simulation sim(m, p, {.construction = Construction({}, {}, 1), .params = undamped});
    sim.refreshForces();
    const double e0 = sim.stats().forces.pairEnergy + kineticEnergy(*m, sim.particles());
    const double scale = std::abs(sim.stats().forces.pairEnergy);
    double worst = 0;
    for (int s = 0; s < 10000; ++s) {
        sim.step();
        worst = std::max(worst, std::abs(sim.stats().total() - e0));
    }
    INFO("E0 " << e0 << ", |E_pair(0)| " << scale << ", largest |E - E0| " << worst << ", final E_kin "
               << sim.stats().kinetic);
    CHECK(sim.stats().kinetic > 0.05);  // the cluster moves
    CHECK(worst / scale < 1e-4);
}

TEST_CASE("drag is integrated exactly and runs are deterministic", "[core][integrator]") {
    auto m = mixedModel(true, true, false, 12.0);
    Particles one;
    one.add(Eigen::Vector3d::Constant(10.0), 2, 1);
    one.vel[0] = Eigen::Vector3d(1, 0, 0);
    Simulation sim(m, one, {.construction = Construction({}, {}, 3), .params = mixedParams(true, true)});
    sim.run(100);
    // A free particle with drag beta_v = 1: v(t) = v0 exp(-t), x(t) = x0 + v0 (1 - exp(-t)) (to O(dt^2)).
    const double t = 100 * m->integration.dt;
    CHECK(sim.particles().vel[0].x() == Approx(std::exp(-t)).epsilon(1e-12));
    CHECK(sim.particles().pos[0].x() == Approx(10.0 + (1 - std::exp(-t))).epsilon(1e-4));

    Particles p = randomParticles(*m, 150, 0.7, 9);
    Simulation a(m, p, {.construction = Construction({}, {}, 3), .params = mixedParams(true, true)}),
        b(m, p, {.construction = Construction({}, {}, 3), .params = mixedParams(true, true)});
    a.run(200);
    b.run(200);
    CHECK(a.particles().pos == b.particles().pos);
    CHECK(a.particles().q[7].coeffs() == b.particles().q[7].coeffs());
}

TEST_CASE("a step's rotation equals the axis-angle quaternion on both sides of its series' bound",
          "[core][integrator]") {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 1);
    double worst = 0, worstNorm = 0;
    int series = 0, trig = 0;
    for (double a = 1e-9; a < 0.6; a *= 1.07) {
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
        const Eigen::Quaterniond q = rotationBy(a * axis), ref(Eigen::AngleAxisd(a, axis));
        worst = std::max(worst, (q.coeffs() - ref.coeffs()).cwiseAbs().maxCoeff());
        worstNorm = std::max(worstNorm, std::abs(q.norm() - 1.0));
        (a < 0.1 ? series : trig) += 1;
    }
    INFO(series << " angles below 0.1 rad, " << trig << " above; largest difference " << worst);
    CHECK(series > 200);
    CHECK(trig > 10);
    CHECK(worst < 4e-16);
    CHECK(worstNorm < 4e-16);
}

TEST_CASE("an undamped cluster of oriented particles conserves energy", "[core][conservation]") {
    auto m = mixedModel(true, false, false, 14.0);
    Particles p = randomParticles(*m, 60, 0.8, 11);
    for (auto& x : p.pos) x = Eigen::Vector3d::Constant(7 * kR0) + 0.75 * (x - Eigen::Vector3d::Constant(7 * kR0));
    Simulation sim(m, p, {.construction = Construction({}, {}, 3), .params = mixedParams(true, false)});
    sim.refreshForces();
    const double e0 = sim.stats().forces.pairEnergy + kineticEnergy(*m, sim.particles());
    double worst = 0;
    for (int s = 0; s < 2000; ++s) {
        sim.step();
        worst = std::max(worst, std::abs(sim.stats().total() - e0));
    }
    INFO("E0 " << e0 << ", largest |E - E0| " << worst << ", final E_kin " << sim.stats().kinetic);
    CHECK(worst < 1e-3 * std::abs(e0));
}

TEST_CASE("a run's trajectory is the same to the last bit at 1, 2 and 3 threads", "[core][threads]") {
    // Surface and volume species, asymmetric weights, a periodic box: every pair loop, halo-free.
    auto m = mixedModel(false, true, true, 16.0);
    const Particles p = randomParticles(*m, 1500, 0.6, 11);
    const int before = threadCount();
    std::vector<Particles> ends;
    std::vector<double> energies;
    std::size_t chunks = 0;
    for (int threads : {1, 2, 3}) {
        setThreadCount(threads);
        Simulation sim(m, p, {.construction = Construction({}, {}, 3), .params = mixedParams(false, true)});
        sim.run(150);
        ends.push_back(sim.particles());
        energies.push_back(sim.stats().total());
        chunks = sim.forceField().pairs().chunks();
    }
    setThreadCount(before);
    INFO("pair chunks " << chunks << ", energies " << energies[0] << " " << energies[1] << " " << energies[2]);
    CHECK(chunks > 3);  // the work is split: the threads share it
    for (std::size_t k = 1; k < ends.size(); ++k) {
        CHECK(ends[k].pos == ends[0].pos);
        CHECK(ends[k].vel == ends[0].vel);
        CHECK(ends[k].omega == ends[0].omega);
        CHECK(ends[k].normal == ends[0].normal);
        CHECK(energies[k] == energies[0]);
    }
    // It moved: the comparison is of trajectories, not of a state at rest.
    double moved = 0;
    for (std::size_t i = 0; i < p.size(); ++i) moved = std::max(moved, (ends[0].pos[i] - p.pos[i]).norm());
    CHECK(moved > 0.01);
}

TEST_CASE("the step's closing kick gives each of its sums to the bit as its own pass would",
          "[core][dynamics][threads]") {
    const auto m = mixedModel(false, true, false, 20);
    const DragFactors drag(*m, mixedParams(false, true));
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-1, 1);
    Particles start;
    for (std::uint64_t k = 0; k < 3000; ++k) {  // several sum blocks, on the threads
        start.add(Eigen::Vector3d(u(rng) + 10, u(rng) + 10, u(rng) + 10) * kR0, 1 + int(k % 3), k + 1);
        start.vel.back() = {u(rng), u(rng), u(rng)};
        start.omega.back() = {u(rng), u(rng), u(rng)};
        start.force.back() = {u(rng), u(rng), u(rng)};
        start.torque.back() = {u(rng), u(rng), u(rng)};
    }
    const SoundBounds bounds(*m);
    std::vector<KickSums> at;
    const int before = threadCount();
    for (int threads : {1, 2, 3}) {
        setThreadCount(threads);
        Particles p = start;
        const KickSums k = kickAndSum(*m, drag, p);
        at.push_back(k);
        // Each sum again, in its own pass over the kicked particles.
        const double twice = sumIndex(p.size(), [&](std::size_t i) {
            const double v2 = p.vel[i].squaredNorm();
            return m->isSurface(p.species[i]) ? v2 + m->integration.inertia * p.omega[i].squaredNorm() : v2;
        });
        const BloodSums blood = bloodSums(*m, p);
        const double soundTerms = sumIndex(p.size(), [&](std::size_t i) { return bounds.term(p, i); });
        CHECK(k.kinetic == 0.5 * twice);
        CHECK(k.kinetic == Approx(kineticEnergy(*m, p)).epsilon(1e-13));
        CHECK(k.volumeMv2 == blood.mv2);
        CHECK(k.volumeCount == blood.count);
        CHECK(k.volumeCount == 1000);
        CHECK(k.soundTerms == soundTerms);
        CHECK(std::isfinite(k.soundTerms));
        CHECK(sound(*m, p, Eigen::Vector3d::Zero()));
    }
    setThreadCount(before);
    for (const KickSums& k : at) {  // the same bits at 1, 2 and 3 threads
        CHECK(k.kinetic == at[0].kinetic);
        CHECK(k.volumeMv2 == at[0].volumeMv2);
        CHECK(k.soundTerms == at[0].soundTerms);
    }
    // A force that is not finite, or a particle far beyond the box, makes the soundness sum so.
    Particles bad = start;
    bad.force[1234].y() = std::numeric_limits<double>::infinity();
    CHECK_FALSE(std::isfinite(kickAndSum(*m, drag, bad).soundTerms));
    bad = start;
    bad.pos[77].x() = 2 * kRunawayLength;
    CHECK_FALSE(std::isfinite(kickAndSum(*m, drag, bad).soundTerms));
}
