#pragma once
// Damped velocity Verlet with exact drag and exact rotation (docs/physics.md §3.2), split as
// O-B-A | forces | B-O:
//   O: v *= exp(-beta_v dt / 2m), omega *= exp(-beta_tau dt / 2I)   (exact half step of the drag)
//   B: v += dt/2 F/m, omega += dt/2 tau/I
//   A: p += dt v;  q = exp(dt omega / 2) q (rotation by |omega| dt about omega), normal = q e_z
// After each B, |v| dt and |omega| dt are held within Integration::maxStepR0 r0 and maxTurn.
// Mass 1; surface particles rotate with inertia I, volume particles do not rotate.
#include "Fire.hpp"
#include "Model.hpp"
#include "Params.hpp"
#include "Particles.hpp"

namespace bop::core {

// The step's length dt; per species exp(-beta_v dt / 2) and exp(-beta_tau dt / (2 I)), the drag's
// exact half step; and the speed limits of Integration::maxStepR0 and maxTurn at dt. Built when
// the drags change, outside the step loop.
struct DragFactors {
    double dt = 0;  // simulation time units
    std::vector<double> v, w;
    double maxSpeed2 = 0, maxSpin2 = 0;  // (length / time)^2 and (radians / time)^2; 0: no limit
    DragFactors(const Model& m, const Params& p) : DragFactors(m, p, m.integration.dt) {}  // the scene's step
    DragFactors(const Model& m, const Params& p, double dt);  // a step of dt (the minimiser's, Fire.hpp)
};

// O, B and A; wraps positions into `box` (the process's region) along its periodic axes unless
// wrap = false (a decomposed run wraps when particles migrate, so halo positions stay continuous
// in between).
// With `fire`, the minimiser's step (Fire.hpp): a stop first (velocities to zero, positions
// back), and after B the velocities turned towards the forces.
void kickDrift(const Model& model, const Box& box, const DragFactors& drag, Particles& p, bool wrap = true,
               const FireKick* fire = nullptr);
// B and O with the forces of the new positions, and in the same pass the sums a step ends with,
// each the same bits as its own pass would give: the kinetic energy afterwards (the value of
// kineticEnergy()), the volume particles' sum of m v^2 and their count (bloodSums()), and the
// particles' soundness sum (SoundBounds::term; sound() adds the probe's reaction).
struct KickSums {
    double kinetic = 0, volumeMv2 = 0, volumeCount = 0, soundTerms = 0;
};
KickSums kickAndSum(const Model& model, const DragFactors& drag, Particles& p);

// Kinetic energy: sum of v^2/2 + I omega^2/2 over particles, energy units.
double kineticEnergy(const Model& model, const Particles& p);

// The rotation by |theta| radians about theta, exp(theta / 2) as a unit quaternion: below 0.1
// radians (every sound step: a turn is limited to max_turn_rad) the Taylor series of cos(a / 2)
// and sin(a / 2) / a, exact to rounding, without a square root, sine or cosine.
Eigen::Quaterniond rotationBy(const Eigen::Vector3d& theta);

// Shortest-arc rotation that carries e_z to n (docs/physics.md §3.3).
Eigen::Quaterniond orientationFor(const Eigen::Vector3d& n);

}  // namespace bop::core
