// Pair potentials (docs/physics.md §1–§2): forces are minus the gradient of the energies (central
// finite differences), torques match the energy's dependence on orientation (dE = -tau.dtheta),
// total angular momentum is conserved pair by pair, and the LJ-form values of docs/physics.md §2.
#include "core/Potentials.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <vector>

using namespace bop::core;
using Eigen::Vector3d;

namespace {

constexpr int kPairs = 200;
constexpr double kStep = 1e-3;    // FD step for positions (fourth-order stencil), length units
constexpr double kAngle = 1e-5;   // FD step for rotations (two-point), radians
constexpr double kRelTol = 1e-6;  // relative error allowed between analytic and FD values
constexpr double kFloor = 1e-3;   // absolute floor of the relative error's denominator
constexpr double kMomentumTol = 1e-12;

Vector3d randomUnit(std::mt19937& rng) {
    std::normal_distribution<double> g;
    Vector3d v;
    do v = Vector3d(g(rng), g(rng), g(rng));
    while (v.norm() < 1e-6);
    return v.normalized();
}

// A random pair vector with length uniform in [rmin, rmax].
Vector3d randomSeparation(std::mt19937& rng, double rmin, double rmax) {
    return std::uniform_real_distribution<double>(rmin, rmax)(rng) * randomUnit(rng);
}

Vector3d randomPoint(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-5.0, 5.0);
    return Vector3d(u(rng), u(rng), u(rng));
}

// -grad E at x by fourth-order central differences (the switched LJ energy is a sum of terms of
// size ~100 that cancel, so its rounding noise ~1e-14 needs a larger step than a 2-point rule).
Vector3d fdForce(const std::function<double(const Vector3d&)>& e, const Vector3d& x) {
    Vector3d f;
    for (int k = 0; k < 3; ++k) {
        auto at = [&](double d) {
            Vector3d y = x;
            y[k] += d;
            return e(y);
        };
        f[k] = -(8.0 * (at(kStep) - at(-kStep)) - (at(2 * kStep) - at(-2 * kStep))) / (12.0 * kStep);
    }
    return f;
}

// -dE/dtheta about each axis, rotating the normal n by +-kAngle: equals tau under dE = -tau.dtheta.
Vector3d fdTorque(const std::function<double(const Vector3d&)>& e, const Vector3d& n) {
    Vector3d tau;
    for (int k = 0; k < 3; ++k) {
        const Vector3d axis = Vector3d::Unit(k);
        const Vector3d np = Eigen::AngleAxisd(kAngle, axis) * n;
        const Vector3d nm = Eigen::AngleAxisd(-kAngle, axis) * n;
        tau[k] = -(e(np) - e(nm)) / (2.0 * kAngle);
    }
    return tau;
}

double relErr(const Vector3d& fd, const Vector3d& exact) {
    return (fd - exact).norm() / std::max(exact.norm(), kFloor);
}

// Central pair forms (LJ, probe): eval(r2, fOverR, energy) with the force on the second particle
// fOverR * (p_2 - p_1). Checks it against -grad E for both particles, and r x F = 0.
template <class Form>
void checkCentralPair(const Form& form, double rmin, double rmax, unsigned seed) {
    auto energy = [&](const Vector3d& a, const Vector3d& b) {
        double fr = 0.0, e = 0.0;
        form.eval((b - a).squaredNorm(), fr, e);
        return e;
    };
    std::mt19937 rng(seed);
    double worst = 0.0, worstMomentum = 0.0;
    for (int n = 0; n < kPairs; ++n) {
        const Vector3d pi = randomPoint(rng);
        const Vector3d pj = pi + randomSeparation(rng, rmin, rmax);
        double fr = 0.0, e = 0.0;
        form.eval((pj - pi).squaredNorm(), fr, e);
        const Vector3d fj = fr * (pj - pi), fi = -fj;
        const Vector3d fdj = fdForce([&](const Vector3d& x) { return energy(pi, x); }, pj);
        const Vector3d fdi = fdForce([&](const Vector3d& x) { return energy(x, pj); }, pi);
        worst = std::max({worst, relErr(fdj, fj), relErr(fdi, fi)});
        worstMomentum = std::max(worstMomentum, (pi.cross(fi) + pj.cross(fj)).norm());
    }
    INFO("worst relative FD error " << worst << ", worst angular-momentum residual " << worstMomentum);
    CHECK(worst < kRelTol);
    CHECK(worstMomentum < kMomentumTol);
}

using OrientedFn = void (*)(const Vector3d&, double, const Vector3d&, const Vector3d&, double, double, OrientedPair&);

OrientedPair orientedPair(OrientedFn fn, const OrientedWeight& w, const Vector3d& pi, const Vector3d& pj,
                          const Vector3d& ni, const Vector3d& nj) {
    const Vector3d r = pj - pi;
    const double rlen = r.norm();
    double psi = 0.0, dpsi = 0.0;
    w.eval(rlen, psi, dpsi);
    OrientedPair out;
    fn(r, rlen, ni, nj, psi, dpsi, out);
    return out;
}

void checkOrientedPair(OrientedFn fn, const OrientedWeight& w, unsigned seed) {
    std::mt19937 rng(seed);
    double worstF = 0.0, worstT = 0.0, worstMomentum = 0.0;
    for (int n = 0; n < kPairs; ++n) {
        const Vector3d pi = randomPoint(rng);
        const Vector3d pj = pi + randomSeparation(rng, 0.3 * kR0, w.cutoff() - 1e-2);
        const Vector3d ni = randomUnit(rng), nj = randomUnit(rng);
        const OrientedPair p = orientedPair(fn, w, pi, pj, ni, nj);
        auto energy = [&](const Vector3d& a, const Vector3d& b, const Vector3d& na, const Vector3d& nb) {
            return orientedPair(fn, w, a, b, na, nb).energy;
        };
        const Vector3d fdj = fdForce([&](const Vector3d& x) { return energy(pi, x, ni, nj); }, pj);
        const Vector3d fdi = fdForce([&](const Vector3d& x) { return energy(x, pj, ni, nj); }, pi);
        const Vector3d tdi = fdTorque([&](const Vector3d& m) { return energy(pi, pj, m, nj); }, ni);
        const Vector3d tdj = fdTorque([&](const Vector3d& m) { return energy(pi, pj, ni, m); }, nj);
        worstF = std::max({worstF, relErr(fdj, p.fj), relErr(fdi, -p.fj)});
        worstT = std::max({worstT, relErr(tdi, p.taui), relErr(tdj, p.tauj)});
        const Vector3d l = p.taui + p.tauj + pi.cross(-p.fj) + pj.cross(p.fj);
        worstMomentum = std::max(worstMomentum, l.norm());
    }
    INFO("worst FD errors: force " << worstF << ", torque " << worstT << "; angular momentum " << worstMomentum);
    CHECK(worstF < kRelTol);
    CHECK(worstT < kRelTol);
    CHECK(worstMomentum < kMomentumTol);
}

}  // namespace

TEST_CASE("LJ-form force is minus the energy gradient in every cutoff mode", "[core][potentials]") {
    const std::vector<LjParams> cases = {
        {LjCutoff::Switched, 1.2, 1.6},      {LjCutoff::Switched, 2.0, 3.0},     {LjCutoff::Truncated, 1.2, 3.0},
        {LjCutoff::EnergyShifted, 1.2, 3.0}, {LjCutoff::ShiftedForce, 1.2, 3.0}, {LjCutoff::ShiftedForce, 1.2, 2.0},
    };
    unsigned seed = 11;
    for (const LjParams& c : cases) {
        const LjForm lj(c);
        INFO("mode " << int(c.mode) << ", rOn " << c.rOnR0 << " r0, rCut " << c.rCutR0 << " r0");
        checkCentralPair(lj, 0.7 * kR0, lj.cutoff() - 1e-2, seed++);
    }
}

TEST_CASE("LJ-form values, continuity and cutoff", "[core][potentials]") {
    const double s3 = std::sqrt(3.0);
    const LjForm sw({LjCutoff::Switched, 1.2, 1.6});
    CHECK(sw.cutoff() == Approx(1.6 * s3));
    CHECK(sw.cutoff2() == Approx(1.6 * 1.6 * 3.0));
    CHECK(std::abs(sw.force(s3)) < 1e-14);
    CHECK(sw.energyConstant() == Approx(0.5133).margin(5e-5));
    CHECK(sw.energy(s3) == Approx(-1.0 / s3 + sw.energyConstant()).margin(1e-14));
    CHECK(sw.energy(s3) == Approx(-0.0640).margin(5e-5));
    CHECK(LjForm({LjCutoff::Switched, 2.0, 3.0}).energyConstant() == Approx(0.3298).margin(5e-5));
    const double eps = 1e-9;
    for (double at : {1.2 * kR0, 1.6 * kR0}) {
        CHECK(sw.force(at - eps) == Approx(sw.force(at + eps)).margin(1e-8));
        CHECK(sw.energy(at - eps) == Approx(sw.energy(at + eps)).margin(1e-8));
    }
    CHECK(std::abs(sw.force(1.6 * kR0 - eps)) < 1e-12);
    CHECK(std::abs(sw.energy(1.6 * kR0 - eps)) < 1e-12);
    for (double beyond : {1.6 * kR0, 1.6 * kR0 + 1e-12, 3.0 * kR0, 100.0}) {
        CHECK(sw.force(beyond) == 0.0);
        CHECK(sw.energy(beyond) == 0.0);
        double fr = 1.0, e = 1.0;
        CHECK_FALSE(sw.eval(beyond * beyond, fr, e));
        CHECK(fr == 0.0);
        CHECK(e == 0.0);
    }

    const LjForm tr({LjCutoff::Truncated, 1.2, 3.0});
    const double rc = 3.0 * kR0;
    CHECK(tr.force(rc * (1 - 1e-12)) == Approx(-4.0 / 81.0).epsilon(1e-9));
    CHECK(tr.energy(rc * (1 - 1e-12)) == Approx(-13.0 * s3 / 81.0).epsilon(1e-9));
    CHECK(tr.energy(s3) == Approx(-1.0 / s3).epsilon(1e-14));
    CHECK(tr.force(rc) == 0.0);

    const LjForm es({LjCutoff::EnergyShifted, 1.2, 3.0});
    CHECK(std::abs(es.energy(rc * (1 - 1e-12))) < 1e-9);
    CHECK(es.force(rc * (1 - 1e-12)) == Approx(-4.0 / 81.0).epsilon(1e-9));

    const LjForm sf({LjCutoff::ShiftedForce, 1.2, 3.0});
    CHECK(std::abs(sf.force(rc * (1 - 1e-12))) < 1e-9);
    CHECK(std::abs(sf.energy(rc * (1 - 1e-12))) < 1e-9);
    const double rMin = 3.0 * std::sqrt(6.0) / 4.0;  // 1.837, docs/physics.md §2.2
    CHECK(std::abs(sf.force(rMin)) < 1e-14);
    CHECK(sf.energy(rMin) < sf.energy(rMin - 1e-3));
    CHECK(sf.energy(rMin) < sf.energy(rMin + 1e-3));
    CHECK(sf.energy(rMin) == Approx(-0.131).margin(5e-4));
}

TEST_CASE("the branch-free LJ force of the pair loop equals the evaluator's in every mode", "[core][potentials]") {
    for (const LjParams& c : {LjParams{LjCutoff::Switched, 1.2, 1.6}, LjParams{LjCutoff::Switched, 2.0, 3.0},
                              LjParams{LjCutoff::Truncated, 1.2, 2.99}, LjParams{LjCutoff::EnergyShifted, 1.2, 2.5},
                              LjParams{LjCutoff::ShiftedForce, 1.2, 2.5}}) {
        const LjForm lj(c);
        double worst = 0;
        int inSwitch = 0;
        for (double r = 0.6 * kR0; r < lj.cutoff(); r += 1e-3) {
            double expected = 0, e = 0;
            REQUIRE(lj.eval(r * r, expected, e));
            worst = std::max(worst, std::abs(lj.forceOverR(r * r) - expected) / std::max(1.0, std::abs(expected)));
            inSwitch += r > lj.switchOn();
        }
        INFO("mode " << int(c.mode) << ", cutoff " << c.rCutR0 << " r0: " << inSwitch << " samples in the switch");
        CHECK(worst < 1e-13);
        CHECK((inSwitch > 100) == (c.mode == LjCutoff::Switched));
    }
}

TEST_CASE("LJ-form and oriented parameters are validated", "[core][potentials]") {
    CHECK_THROWS_AS(LjForm({LjCutoff::Switched, 1.6, 1.6}), std::invalid_argument);
    CHECK_THROWS_AS(LjForm({LjCutoff::Switched, 0.0, 1.6}), std::invalid_argument);
    CHECK_THROWS_AS(LjForm({LjCutoff::Truncated, 1.2, 0.0}), std::invalid_argument);
    CHECK_NOTHROW(LjForm({LjCutoff::Truncated, 1.2, 1.0}));  // rOn ignored without a switch
    CHECK_THROWS_AS(OrientedWeight({0.0, 2.0, 3.0}), std::invalid_argument);
    CHECK_THROWS_AS(OrientedWeight({1.0, 3.0, 3.0}), std::invalid_argument);
    CHECK_THROWS_AS(ProbeForm(LjForm(), {0.0, 1.0}), std::invalid_argument);
}

TEST_CASE("Oriented weight: Gaussian times taper, derivative, cutoff", "[core][potentials]") {
    const OrientedWeight w;
    CHECK(w.cutoff() == Approx(3.0 * kR0));
    double psi = 0.0, dpsi = 0.0;
    REQUIRE(w.eval(kR0, psi, dpsi));
    CHECK(psi == Approx(std::exp(-0.5)));
    for (double r : {0.5, 1.0 * kR0, 2.0 * kR0 + 0.3, 2.9 * kR0}) {
        double pp = 0.0, pm = 0.0, d = 0.0;
        w.eval(r, psi, dpsi);
        const double h = 1e-5;  // length
        w.eval(r + h, pp, d);
        w.eval(r - h, pm, d);
        CHECK((pp - pm) / (2 * h) == Approx(dpsi).epsilon(1e-7));
    }
    CHECK(w.eval(3.0 * kR0 - 1e-9, psi, dpsi));
    CHECK(std::abs(psi) < 1e-15);
    CHECK_FALSE(w.eval(3.0 * kR0, psi, dpsi));
    CHECK(psi == 0.0);
    CHECK(dpsi == 0.0);
}

TEST_CASE("Co-normal force and torques match the energy", "[core][potentials]") {
    checkOrientedPair(&coNormal, OrientedWeight(), 21);
    checkOrientedPair(&coNormal, OrientedWeight({0.7, 1.5, 2.5}), 22);
}

TEST_CASE("Co-planar force and torques match the energy", "[core][potentials]") {
    checkOrientedPair(&coPlanar, OrientedWeight(), 31);
    checkOrientedPair(&coPlanar, OrientedWeight({0.7, 1.5, 2.5}), 32);
    // Both particles in each other's tangent plane: no energy, force or torque.
    OrientedPair p;
    coPlanar(Vector3d(2, 0, 0), 2.0, Vector3d::UnitZ(), Vector3d::UnitZ(), 0.5, -0.1, p);
    CHECK(p.energy == 0.0);
    CHECK(p.fj.norm() == 0.0);
    CHECK(p.taui.norm() == 0.0);
}

TEST_CASE("The same-sheet gate: opposite faces of a thin part feel no oriented pair", "[core][potentials]") {
    // Two particles 1.2 r0 apart across a plate, normals facing away from each other (the plate's
    // two faces), then the same pair on one face (normals alike) and at 100 degrees (partly gated).
    const OrientedWeight w;
    const Vector3d pi(0, 0, 0), pj(0, 0, 1.2 * kR0);
    for (OrientedFn fn : {&coNormal, &coPlanar}) {
        const OrientedPair across = orientedPair(fn, w, pi, pj, -Vector3d::UnitZ(), Vector3d::UnitZ());
        CHECK(across.energy == 0.0);
        CHECK(across.fj.norm() == 0.0);
        CHECK(across.taui.norm() == 0.0);
        CHECK(across.tauj.norm() == 0.0);
        const Vector3d tilted(std::sin(1.2), 0, std::cos(1.2));               // 69 degrees from z
        const Vector3d apart(std::sin(1.2 + 0.55), 0, std::cos(1.2 + 0.55));  // 100 degrees from z
        const OrientedPair near = orientedPair(fn, w, pi, pj + Vector3d(0.3, 0, 0), Vector3d::UnitZ(), tilted);
        const OrientedPair far = orientedPair(fn, w, pi, pj + Vector3d(0.3, 0, 0), Vector3d::UnitZ(), apart);
        CHECK(near.energy > 0.0);
        CHECK(far.energy > 0.0);  // c = cos(100 deg) = -0.17: g = 0.21
        CHECK(far.energy < near.energy);
    }
}

TEST_CASE("Probe force is minus the energy gradient and scales with k0, k1", "[core][potentials]") {
    const ProbeParams pp{1.7, 2.3};
    for (const LjParams& c : {LjParams{}, LjParams{LjCutoff::Truncated, 1.2, 3.0}}) {
        const LjForm lj(c);
        const ProbeForm probe(lj, pp);
        CHECK(probe.cutoff() == Approx(1.7 * lj.cutoff()));
        // The force on the particle (second point) is fOverR (p_i - probe) = -dE/dp_i.
        checkCentralPair(probe, 0.7 * pp.k0 * kR0, probe.cutoff() - 1e-2, 41);
        // Equilibrium at k0 r0, energy scaled by k1 k0, force by k1.
        double fr = 1.0, e = 0.0;
        const double req = pp.k0 * kR0;
        REQUIRE(probe.eval(req * req, fr, e));
        CHECK(std::abs(fr) < 1e-14);
        CHECK(e == Approx(pp.k1 * pp.k0 * lj.energy(kR0)).epsilon(1e-12));
        probe.eval(std::pow(pp.k0 * 1.1, 2), fr, e);
        CHECK(fr * pp.k0 * 1.1 == Approx(pp.k1 * lj.force(1.1)).epsilon(1e-12));
        CHECK_FALSE(probe.eval(probe.cutoff2(), fr, e));
    }
}
