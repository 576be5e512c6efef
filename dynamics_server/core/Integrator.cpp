#include "Integrator.hpp"

#include "SoundState.hpp"
#include "Threads.hpp"

#include <array>
#include <cmath>

namespace bop::core {
namespace {

// v scaled down to the speed limit (max2 = 0: none). A branch no sound step takes.
inline void limit(Eigen::Vector3d& v, double max2) {
    const double v2 = v.squaredNorm();
    if (max2 > 0 && v2 > max2) v *= std::sqrt(max2 / v2);
}

}  // namespace

DragFactors::DragFactors(const Model& m, const Params& p, double step)
    : dt(step),
      v(m.species.size(), 1.0),
      w(m.species.size(), 1.0),
      maxSpeed2(std::pow(m.integration.maxStepR0 * kR0 / step, 2)),
      maxSpin2(std::pow(m.integration.maxTurn / step, 2)) {
    for (std::size_t s = 1; s < m.species.size(); ++s) {
        v[s] = std::exp(-p.drag[s].v * dt / 2.0);
        w[s] = std::exp(-p.drag[s].w * dt / (2.0 * m.integration.inertia));
    }
}

void kickDrift(const Model& model, const Box& box, const DragFactors& decay, Particles& p, bool wrap,
               const FireKick* fire) {
    const double dt = decay.dt, half = 0.5 * dt, invI = 1.0 / model.integration.inertia;
    const Eigen::Vector3d lo = box.lo, hi = box.hi, L = box.size();
    const bool anyPeriodic = wrap && (box.periodic[0] || box.periodic[1] || box.periodic[2]);
    forEachIndex(p.size(), [&](std::size_t i) {  // each particle on its own: on the threads
        const int s = p.species[i];
        if (fire && fire->stop) {
            p.pos[i] -= fire->back * p.vel[i];
            p.vel[i].setZero();
            p.omega[i].setZero();
        }
        p.vel[i] = decay.v[std::size_t(s)] * p.vel[i] + half * p.force[i];
        if (fire) p.vel[i] = fire->keep * p.vel[i] + fire->alongForce * p.force[i];
        limit(p.vel[i], decay.maxSpeed2);
        p.pos[i] += dt * p.vel[i];
        if (anyPeriodic)
            for (int a = 0; a < 3; ++a)
                if (box.periodic[std::size_t(a)] && (p.pos[i][a] < lo[a] || p.pos[i][a] >= hi[a]))
                    p.pos[i][a] -= L[a] * std::floor((p.pos[i][a] - lo[a]) / L[a]);
        if (!model.isSurface(s)) return;
        p.omega[i] = decay.w[std::size_t(s)] * p.omega[i] + half * invI * p.torque[i];
        if (fire) p.omega[i] = fire->keep * p.omega[i] + fire->alongTorque * p.torque[i];
        limit(p.omega[i], decay.maxSpin2);
        p.q[i] = (rotationBy(dt * p.omega[i]) * p.q[i]).normalized();
        p.normal[i] = p.q[i] * Eigen::Vector3d::UnitZ();
    });
}

namespace {

// B and O of particle i (half: dt / 2; invI: 1 / I); returns its v^2 + I omega^2 (twice its
// kinetic energy, unit mass).
inline double kickOne(const Model& model, const DragFactors& decay, double half, double invI, Particles& p,
                      std::size_t i) {
    const int s = p.species[i];
    p.vel[i] = decay.v[std::size_t(s)] * (p.vel[i] + half * p.force[i]);
    limit(p.vel[i], decay.maxSpeed2);
    const double v2 = p.vel[i].squaredNorm();
    if (!model.isSurface(s)) return v2;
    p.omega[i] = decay.w[std::size_t(s)] * (p.omega[i] + half * invI * p.torque[i]);
    limit(p.omega[i], decay.maxSpin2);
    return v2 + model.integration.inertia * p.omega[i].squaredNorm();
}

}  // namespace

KickSums kickAndSum(const Model& model, const DragFactors& decay, Particles& p) {
    const SoundBounds bounds(model);
    const double half = 0.5 * decay.dt, invI = 1.0 / model.integration.inertia;
    // On the threads, each sum in fixed blocks.
    const std::array<double, 4> sums = sumsIndex<4>(p.size(), [&](std::size_t i) {
        const double twiceKinetic = kickOne(model, decay, half, invI, p, i);
        const bool volume = !model.isSurface(p.species[i]);
        return std::array<double, 4>{twiceKinetic, volume ? p.vel[i].squaredNorm() : 0.0, volume ? 1.0 : 0.0,
                                     bounds.term(p, i)};
    });
    return {0.5 * sums[0], sums[1], sums[2], sums[3]};
}

double kineticEnergy(const Model& model, const Particles& p) {
    return sumIndex(p.size(), [&](std::size_t i) {  // on the threads, in fixed blocks
        double e = 0.5 * p.vel[i].squaredNorm();
        if (model.isSurface(p.species[i])) e += 0.5 * model.integration.inertia * p.omega[i].squaredNorm();
        return e;
    });
}

Eigen::Quaterniond rotationBy(const Eigen::Vector3d& theta) {
    const double a2 = theta.squaredNorm();
    double c, s;      // cos(a / 2) and sin(a / 2) / a, a = |theta|
    if (a2 < 0.01) {  // the series to a^8: the first term left out is below 3e-20
        c = 1.0 + a2 * (-1.0 / 8 + a2 * (1.0 / 384 + a2 * (-1.0 / 46080 + a2 * (1.0 / 10321920))));
        s = 0.5 + a2 * (-1.0 / 48 + a2 * (1.0 / 3840 + a2 * (-1.0 / 645120 + a2 * (1.0 / 185794560))));
    } else {
        const double a = std::sqrt(a2);
        c = std::cos(0.5 * a);
        s = std::sin(0.5 * a) / a;
    }
    return Eigen::Quaterniond(c, s * theta.x(), s * theta.y(), s * theta.z());
}

Eigen::Quaterniond orientationFor(const Eigen::Vector3d& n) {
    const Eigen::Vector3d u = n.normalized();
    const double w = 1.0 + u.z();
    if (w < 1e-9) return Eigen::Quaterniond(0, 1, 0, 0);
    const Eigen::Vector3d c = Eigen::Vector3d::UnitZ().cross(u);
    return Eigen::Quaterniond(w, c.x(), c.y(), c.z()).normalized();
}

}  // namespace bop::core
