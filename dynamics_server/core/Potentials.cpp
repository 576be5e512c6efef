// Pair potentials: constructors (parameter checks, precomputed constants) and the oriented-pair
// force/torque formulas of docs/physics.md §1.2.
#include "Potentials.hpp"

#include <stdexcept>
#include <string>

namespace bop::core {

namespace {

double ljPhi(double r) {
    return 1.5 * (1.0 / (r * r * r) - 1.0 / r);
}  // phi(r), energy
double ljForce(double r) {
    return 4.5 / (r * r * r * r) - 1.5 / (r * r);
}  // f(r) = -phi'(r)

bool positiveFinite(double x) {
    return std::isfinite(x) && x > 0.0;
}

}  // namespace

LjForm::LjForm(const LjParams& p) : params_(p) {
    if (!positiveFinite(p.rCutR0))
        throw std::invalid_argument("LJ form: cutoff must be > 0 (got " + std::to_string(p.rCutR0) + " r0)");
    rc_ = p.rCutR0 * kR0;
    rc2_ = rc_ * rc_;
    rOn_ = rc_;
    switch (p.mode) {
        case LjCutoff::Truncated:
            break;
        case LjCutoff::EnergyShifted:
            c_ = -ljPhi(rc_);
            break;
        case LjCutoff::ShiftedForce:
            // phi - phi(rc) - (r - rc) phi'(rc) = phi + f(rc) r - (phi(rc) + f(rc) rc)
            fShift_ = ljForce(rc_);
            c_ = -ljPhi(rc_) - fShift_ * rc_;
            break;
        case LjCutoff::Switched: {
            if (!positiveFinite(p.rOnR0) || !(p.rOnR0 < p.rCutR0))
                throw std::invalid_argument("LJ form: switch needs 0 < rOn < rCut (got rOn " + std::to_string(p.rOnR0) +
                                            " r0, rCut " + std::to_string(p.rCutR0) + " r0)");
            const double a = p.rOnR0 * kR0;
            const double w = rc_ - a;
            rOn_ = a;
            invWidth_ = 1.0 / w;
            // S(r) = s0 + s1 r + s2 r^2 + s3 r^3 (the taper expanded in powers of r).
            const double w2 = w * w, w3 = w2 * w;
            const double s0 = 1.0 - 3.0 * a * a / w2 - 2.0 * a * a * a / w3;
            const double s1 = 6.0 * a / w2 + 6.0 * a * a / w3;
            const double s2 = -3.0 / w2 - 6.0 * a / w3;
            const double s3 = 2.0 / w3;
            // f S = sum_k q_k r^k for k = -4..1; G is its antiderivative (the r^-1 term gives ln r).
            const double qm4 = 4.5 * s0, qm3 = 4.5 * s1, qm2 = 4.5 * s2 - 1.5 * s0;
            const double qm1 = 4.5 * s3 - 1.5 * s1, q0 = -1.5 * s2, q1 = -1.5 * s3;
            a_[0] = -qm4 / 3.0;
            a_[1] = -qm3 / 2.0;
            a_[2] = -qm2;
            a_[3] = qm1;
            a_[4] = q0;
            a_[5] = q1 / 2.0;
            gCut_ = 0.0;
            gCut_ = -switchedEnergy(rc_, 1.0 / rc_, 1.0 / rc2_);  // G(rc)
            c_ = switchedEnergy(a, 1.0 / a, 1.0 / (a * a)) - ljPhi(a);
            break;
        }
    }
    rOn2_ = rOn_ * rOn_;
}

double LjForm::force(double r) const {
    if (!(r < rc_)) return 0.0;
    double fOverR = 0.0, e = 0.0;
    eval(r * r, fOverR, e);
    return fOverR * r;
}

double LjForm::energy(double r) const {
    if (!(r < rc_)) return 0.0;
    double fOverR = 0.0, e = 0.0;
    eval(r * r, fOverR, e);
    return e;
}

OrientedWeight::OrientedWeight(const OrientedParams& p) : params_(p) {
    if (!positiveFinite(p.sigmaR0))
        throw std::invalid_argument("oriented weight: sigma must be > 0 (got " + std::to_string(p.sigmaR0) + " r0)");
    if (!positiveFinite(p.taperOnR0) || !positiveFinite(p.cutoffR0) || !(p.taperOnR0 < p.cutoffR0))
        throw std::invalid_argument("oriented weight: taper needs 0 < taperOn < cutoff (got " +
                                    std::to_string(p.taperOnR0) + " r0, " + std::to_string(p.cutoffR0) + " r0)");
    const double sigma = p.sigmaR0 * kR0;
    rc_ = p.cutoffR0 * kR0;
    rc2_ = rc_ * rc_;
    rOn_ = p.taperOnR0 * kR0;
    invWidth_ = 1.0 / (rc_ - rOn_);
    invS2_ = 1.0 / (sigma * sigma);
    inv2s2_ = 0.5 * invS2_;
}

namespace {

// One term of orientedPair with weight 1 (and the other 0), as an OrientedPair.
void oneTerm(bool normal, const Eigen::Vector3d& r, double rlen, const Eigen::Vector3d& ni, const Eigen::Vector3d& nj,
             double psi, double dpsi, OrientedPair& out) {
    const double cn = normal ? 1.0 : 0.0, cp = 1.0 - cn;
    const OrientedWeights<double> k{cn, cn, cn, cn, cn, cp, cp, cp, cp, cp};
    const OrientedForces<double> o = orientedPair<true>(xyzOf(r), rlen * rlen, inverseOrZero(rlen), xyzOf(ni),
                                                        xyzOf(nj), Psi<double>{psi, dpsi}, 1.0, k);
    out.fj = vectorOf(o.fj);
    out.taui = vectorOf(o.ti);
    out.tauj = vectorOf(o.tj);
    out.energy = o.energy;
}

}  // namespace

void coNormal(const Eigen::Vector3d& r, double rlen, const Eigen::Vector3d& ni, const Eigen::Vector3d& nj, double psi,
              double dpsi, OrientedPair& out) {
    oneTerm(true, r, rlen, ni, nj, psi, dpsi, out);
}

void coPlanar(const Eigen::Vector3d& r, double rlen, const Eigen::Vector3d& ni, const Eigen::Vector3d& nj, double psi,
              double dpsi, OrientedPair& out) {
    oneTerm(false, r, rlen, ni, nj, psi, dpsi, out);
}

ProbeForm::ProbeForm(const LjForm& lj, ProbeParams p) : lj_(lj), params_(p) {
    if (!positiveFinite(p.k0)) throw std::invalid_argument("probe: k0 must be > 0 (got " + std::to_string(p.k0) + ")");
    if (!std::isfinite(p.k1)) throw std::invalid_argument("probe: k1 must be finite");
    rc_ = p.k0 * lj.cutoff();
    rc2_ = rc_ * rc_;
    invK0Sq_ = 1.0 / (p.k0 * p.k0);
    k1OverK0_ = p.k1 / p.k0;
    k1K0_ = p.k1 * p.k0;
    core_ = kProbeCoreR0 * p.k0 * kR0;
    double fr = 0.0, e = 0.0;
    lj_.eval(kProbeCoreR0 * kProbeCoreR0 * kR0 * kR0, fr, e);  // at s = r / k0 on the core's edge
    coreForce_ = fr * kProbeCoreR0 * kR0 * p.k1;               // k1 f(s)
    coreEnergy_ = e * k1K0_;
    core2_ = core_ * core_;
}

}  // namespace bop::core
