#pragma once
// Pair potentials of the dynamics core (docs/physics.md §1–§2), as small evaluators in the HOOMD
// spirit: they turn a squared distance (or a distance) and their parameters into force/r and
// energy, with no allocation, no exceptions and no std::pow on the hot path.
//
// Units: simulation length units throughout (r0 = sqrt(3) is the LJ-form equilibrium spacing);
// parameters with the suffix "R0" are multiples of r0. Energies and forces are in the single
// energy unit of the simulation. Pair vector r = p_j - p_i (from i to j).
//
// - LjForm: phi(r) = 1.5 (r^-3 - r^-1), f(r) = -phi'(r) = 4.5 r^-4 - 1.5 r^-2 (positive =
//   repulsive), with one of four cutoff treatments (docs/physics.md §2.2).
// - OrientedWeight: psi(r) = exp(-r^2 / (2 sigma^2)) S(r) for the oriented-particle energies.
// - coNormal / coPlanar: forces and torques of |n_i - n_j|^2 psi and ((n_i.r)^2 + (n_j.r)^2) psi
//   (docs/physics.md §1.2); torque tau = -n x dE/dn.
// - ProbeForm: the haptic probe, k1 f(r/k0) and k1 k0 phi(r/k0) (paper eq. 9, docs/physics.md §2.4).
//
// S is the cubic taper S = 1 - 3t^2 + 2t^3, t = (r - r_on)/(r_c - r_on), on [r_on, r_c].
#include "OrientedTerms.hpp"
#include "bop/common/Units.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace bop::core {

using bop::kR0;          // r0 = sqrt(3), simulation length units (bop/common/Units.hpp)
using bop::voxelLength;  // a map voxel's edge, simulation length units

enum class LjCutoff {
    Switched,       // force f(r) S(r) on [rOn, rCut]; energy consistent, phi + C below rOn
    Truncated,      // plain phi and f, cut at rCut (paper mode; jumps at rCut)
    EnergyShifted,  // phi - phi(rCut), f unchanged
    ShiftedForce,   // phi - phi(rc) - (r - rc) phi'(rc), f - f(rc)
};

struct LjParams {
    LjCutoff mode = LjCutoff::Switched;  // cutoff treatment
    double rOnR0 = 1.2;                  // switch start, multiples of r0 (used only by Switched)
    double rCutR0 = 1.6;                 // cutoff, multiples of r0 (the paper: Truncated at 3)
};

class LjForm {
public:
    // Throws std::invalid_argument unless 0 < rCut (and, for Switched, 0 < rOn < rCut).
    explicit LjForm(const LjParams& p = {});

    const LjParams& params() const { return params_; }
    double cutoff() const { return rc_; }                // cutoff radius, simulation length units
    double cutoff2() const { return rc2_; }              // squared cutoff, simulation length units^2
    double switchOn() const { return rOn_; }             // start of the switch (= cutoff if none), length
    double energyConstant() const { return c_; }         // constant C added to phi below rOn (energy)
    double invSwitchWidth() const { return invWidth_; }  // 1 / (rc - rOn), 1/length; 0 without a switch
    double forceShift() const { return fShift_; }        // f(rc) subtracted by ShiftedForce, else 0

    // r2: squared distance (> 0), length^2. Outputs fOverR = f(r)/r (energy / length^2; the
    // force on j is fOverR * (p_j - p_i)) and the pair energy. Returns false, with both outputs
    // zero, when r2 >= cutoff2().
    // The force is forceOverR()'s to the last bit: a run's trajectory does not depend on which
    // steps ask for energies.
    bool eval(double r2, double& fOverR, double& energy) const {
        if (r2 >= rc2_) {
            fOverR = 0.0;
            energy = 0.0;
            return false;
        }
        fOverR = forceOverR(r2);
        energy = energyOfR2(r2);
        return true;
    }

    // The energy alone for r2 < cutoff2() (the caller has checked), energy units.
    double energyOfR2(double r2) const {
        const double inv2 = 1.0 / r2;
        const double r = std::sqrt(r2);
        const double inv = 1.0 / r;
        if (r2 <= rOn2_) return 1.5 * (inv2 * inv - inv) + fShift_ * r + c_;
        return switchedEnergy(r, inv, inv2);
    }

    // f(r)/r for r2 < cutoff2() (the caller has checked), without branches: the pair loops'
    // path. Below the switch t clamps to 0 (S = 1); without a switch invWidth_ is 0.
    double forceOverR(double r2) const {
        const double inv2 = 1.0 / r2;  // the division and the root run side by side
        const double r = std::sqrt(r2);
        const double rinv = r * inv2;
        const double f = (4.5 * inv2 - 1.5) * inv2 - fShift_;
        const double u = (r - rOn_) * invWidth_;
        // max(u, 0) exactly, written so that the compiler cannot make it a branch (one that
        // skipped the polynomial mispredicted on rows whose pairs straddle the switch).
        const double t = 0.5 * (u + std::abs(u));
        return f * (1.0 + t * t * (2.0 * t - 3.0)) * rinv;
    }

    // Scalar force (positive = repulsive) and energy at distance r (> 0, length), with the
    // cutoff treatment; both are 0 at and beyond the cutoff.
    double force(double r) const;
    double energy(double r) const;

private:
    // Energy in the switch region: G(rCut) - G(r), G the antiderivative of f S (see .cpp).
    double switchedEnergy(double r, double inv, double inv2) const {
        const double g =
            a_[0] * inv2 * inv + a_[1] * inv2 + a_[2] * inv + a_[3] * std::log(r) + r * (a_[4] + a_[5] * r);
        return gCut_ - g;
    }

    LjParams params_;
    double rc_ = 0.0;        // cutoff, length
    double rc2_ = 0.0;       // cutoff squared, length^2
    double rOn_ = 0.0;       // switch start (= rc_ when not Switched), length
    double rOn2_ = 0.0;      // switch start squared, length^2
    double invWidth_ = 0.0;  // 1 / (rc - rOn), 1/length (0 when not Switched)
    double fShift_ = 0.0;    // f(rc) for ShiftedForce, else 0 (energy/length)
    double c_ = 0.0;         // energy constant below rOn: energy = phi + fShift r + c (energy)
    double a_[6] = {};       // G(r) = a0 r^-3 + a1 r^-2 + a2 r^-1 + a3 ln r + a4 r + a5 r^2
    double gCut_ = 0.0;      // G(rc) (energy)
};

struct OrientedParams {
    double sigmaR0 = 1.0;    // Gaussian width sigma, multiples of r0
    double taperOnR0 = 2.0;  // start of the cubic taper, multiples of r0
    double cutoffR0 = 3.0;   // cutoff of the oriented terms, multiples of r0
};

// psi(r) = exp(-r^2 / (2 sigma^2)) S(r), S the cubic taper on [taperOn, cutoff].
class OrientedWeight {
public:
    // Throws std::invalid_argument unless sigma > 0 and 0 < taperOn < cutoff.
    explicit OrientedWeight(const OrientedParams& p = {});

    const OrientedParams& params() const { return params_; }
    double cutoff() const { return rc_; }    // length
    double cutoff2() const { return rc2_; }  // length^2

    double taperOn() const { return rOn_; }             // length
    double invTaperWidth() const { return invWidth_; }  // 1/length
    double invTwoSigma2() const { return inv2s2_; }     // 1 / (2 sigma^2), 1/length^2
    double invSigma2() const { return invS2_; }         // 1/length^2

    // r: distance, length. Outputs psi (dimensionless) and dpsi = dpsi/dr (1/length). Returns
    // false, with both zero, when r >= cutoff().
    bool eval(double r, double& psi, double& dpsi) const {
        if (r >= rc_) {
            psi = 0.0;
            dpsi = 0.0;
            return false;
        }
        const Psi<double> w = orientedPsi(r * r, r, constants());
        psi = w.psi;
        dpsi = w.dpsi;
        return true;
    }
    // The constants of orientedPsi (OrientedTerms.hpp), the step's loop's too.
    PsiConstants constants() const { return {rOn_, invWidth_, inv2s2_, invS2_}; }

private:
    OrientedParams params_;
    double rc_ = 0.0;        // cutoff, length
    double rc2_ = 0.0;       // cutoff squared, length^2
    double rOn_ = 0.0;       // taper start, length
    double invWidth_ = 0.0;  // 1 / (cutoff - taperOn), 1/length
    double inv2s2_ = 0.0;    // 1 / (2 sigma^2), 1/length^2
    double invS2_ = 0.0;     // 1 / sigma^2, 1/length^2
};

// A vector as OrientedTerms.hpp's evaluator takes and gives it, and back.
inline Xyz<double> xyzOf(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}
inline Eigen::Vector3d vectorOf(const Xyz<double>& v) {
    return {v.x, v.y, v.z};
}

struct OrientedPair {
    Eigen::Vector3d fj;    // force on j (energy/length); F_i = -fj
    Eigen::Vector3d taui;  // torque on i (energy)
    Eigen::Vector3d tauj;  // torque on j (energy)
    double energy;         // pair energy (energy)
};

// Co-normality E = |n_i - n_j|^2 psi(r). r: p_j - p_i (length); rlen = |r| (length); ni, nj:
// unit normals; psi (dimensionless) and dpsi = dpsi/dr (1/length) from OrientedWeight::eval.
void coNormal(const Eigen::Vector3d& r, double rlen, const Eigen::Vector3d& ni, const Eigen::Vector3d& nj, double psi,
              double dpsi, OrientedPair& out);

// Pair-symmetric co-planarity E = ((n_i.r)^2 + (n_j.r)^2) psi(r); arguments as coNormal.
void coPlanar(const Eigen::Vector3d& r, double rlen, const Eigen::Vector3d& ni, const Eigen::Vector3d& nj, double psi,
              double dpsi, OrientedPair& out);

struct ProbeParams {
    double k0 = 1.0;  // range scale, dimensionless (equilibrium spacing k0 r0)
    double k1 = 1.0;  // strength, dimensionless
};

// Probe-particle interaction: force k1 f(r/k0) along the unit vector from the probe to the
// particle, energy k1 k0 phi(r/k0), with the LjForm's cutoff treatment scaled by k0. Closer than
// kProbeCoreR0 k0 r0 the force stays that of kProbeCoreR0 k0 r0 (the energy grows linearly, so
// F = -dE/dr still holds): an overlap no haptic contact reaches, where f(r) grows as r^-4 and a
// probe dropped onto a particle would launch it at near-infinite speed. At r = 0 the force is 0.
inline constexpr double kProbeCoreR0 = 0.5;  // multiples of k0 r0

// The probe as commands set it.
struct ProbeState {
    bool active = false;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // simulation length units
    ProbeParams params;                                  // k0, k1 (eq. 9)
};

class ProbeForm {
public:
    // Throws std::invalid_argument unless k0 > 0 and k1 is finite.
    ProbeForm(const LjForm& lj, ProbeParams p = {});

    const ProbeParams& params() const { return params_; }
    double cutoff() const { return rc_; }    // k0 * lj cutoff, length
    double cutoff2() const { return rc2_; }  // length^2

    // r2: squared probe-particle distance (> 0), length^2. The force on particle i is
    // fOverR * (p_i - probe); energy in energy units. False, with zeros, beyond the cutoff.
    bool eval(double r2, double& fOverR, double& energy) const {
        if (r2 >= rc2_) {
            fOverR = 0.0;
            energy = 0.0;
            return false;
        }
        if (r2 < core2_) {  // the core: the force of its edge, along r
            const double r = std::sqrt(r2);
            fOverR = r > 0.0 ? coreForce_ / r : 0.0;
            energy = coreEnergy_ + coreForce_ * (core_ - r);
            return true;
        }
        double fr = 0.0;
        double e = 0.0;
        lj_.eval(r2 * invK0Sq_, fr, e);
        fOverR = fr * k1OverK0_;  // k1 f(s) / r with s = r / k0, f(s)/s = fr
        energy = e * k1K0_;
        return true;
    }

private:
    LjForm lj_;
    ProbeParams params_;
    double rc_ = 0.0;          // length
    double rc2_ = 0.0;         // length^2
    double invK0Sq_ = 0.0;     // 1 / k0^2
    double k1OverK0_ = 0.0;    // k1 / k0
    double k1K0_ = 0.0;        // k1 k0
    double core_ = 0.0;        // kProbeCoreR0 k0 r0, length
    double core2_ = 0.0;       // length^2
    double coreForce_ = 0.0;   // the force at the core's edge, force
    double coreEnergy_ = 0.0;  // the energy there, energy
};

}  // namespace bop::core
