#pragma once
// FIRE, the fast inertial relaxation engine (Bitzek et al., Phys. Rev. Lett. 97, 170201, 2006),
// with the half step back of its 2.0 form (Guénolé et al., Comput. Mater. Sci. 175, 109584, 2020):
// a minimiser that moves the particles by the dynamics' own velocity Verlet and, every step, turns
// the velocities towards the forces, lengthening the step while the power F·v stays positive and
// stopping dead (with half a step back) when it turns negative. A placed bag settles with it in a
// few hundred steps instead of a thousand or more (docs/physics.md §7.5). Surface particles'
// turns take part: the power is F·v + τ·ω, and ω is turned towards τ as v towards F.
//
// The drag stays on (FIRE is usually run without one): the map's forces jump where a particle
// crosses a voxel face, and those jumps feed energy in that the drag takes out. Without it, the
// 21-bag synthetic scan (at --scale 1) ran up to 0.25 ε of kinetic energy per particle with
// LAMMPS's constants, and swung for 1,160 steps with these (docs/physics.md §7.5).
//
// The decision of a step reads sums over every process (FirePower, added in rank order), so every
// process takes the same one.
#include "Model.hpp"
#include "Particles.hpp"

#include <optional>

namespace bop::core {

// The minimiser's constants: those of Bitzek et al. (2006), except the longest step, 6 instead of
// 10 times the first (measured on the torus and the synthetic scan: docs/physics.md §7.5). A step
// moves a particle at most the scene's max_step_r0 and turns it at most max_turn_rad, as in the
// dynamics.
struct FireParams {
    double dtMaxFactor = 6.0;   // longest step over the scene's time step
    double dtMinFactor = 0.02;  // shortest step over the scene's time step
    double grow = 1.1;          // the step's growth after delaySteps steps of positive power
    double shrink = 0.5;        // its cut when the power turns negative
    double alphaStart = 0.1;    // the weight of the force's direction in the velocity after a stop
    double alphaShrink = 0.99;  // its decay each step of positive power after delaySteps
    long long delaySteps = 5;   // steps of positive power before the step grows
    // The most steps it takes before it hands the run to the dynamics (app/runs/Settling.hpp)
    // even if not calm: where jumps of the map's forces keep the kinetic energy up, the damped
    // dynamics' shorter step holds it lower.
    long long maxSteps = 600;
};

// One process's sums of the state after a step: the power and the squared norms of the
// velocities, forces, angular velocities and torques (unit mass; energy / time, (length / time)^2,
// force^2, (radians / time)^2, torque^2). Sum them over processes in rank order.
struct FirePower {
    double power = 0, vv = 0, ff = 0, ww = 0, tt = 0;
};
FirePower firePower(const Model& model, const Particles& p);  // on the threads, in fixed blocks

// What the next step does with the velocities, decided from the sums of every process.
struct FireKick {
    double dt = 0;           // the step's length, simulation time units
    bool stop = false;       // velocities to zero first, positions back by `back` times them
    double back = 0;         // time units (half the new step)
    double keep = 1;         // v <- keep v + alongForce F after the first half kick
    double alongForce = 0;   // (length / time) / force
    double alongTorque = 0;  // omega <- keep omega + alongTorque tau, (radians / time) / torque
};

// Where the minimiser is: what a checkpoint keeps so that a restart goes on as the run would.
struct FireState {
    double dt = 0;                           // the next step's length before its decision, time units
    double alpha = 0;                        // the force direction's weight
    long long steps = 0, sincePositive = 0;  // steps taken; steps since the power last turned negative
};

class Fire {
public:
    // dt: the scene's time step, the first step's and the unit of the limits; `from`: go on from
    // that state instead of the start.
    Fire(const FireParams& params, double dt, const std::optional<FireState>& from = std::nullopt);
    // The next step, from the sums of the state the last step ended in (every process's).
    FireKick next(const FirePower& sums);
    FireState state() const { return {dt_, alpha_, steps_, sincePositive_}; }

private:
    FireParams params_;
    double dt0_, dt_, alpha_;
    long long steps_ = 0, sincePositive_ = 0;  // steps taken; steps since the power last turned negative
};

}  // namespace bop::core
