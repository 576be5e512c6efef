#pragma once
// Whether a state is one a run may go on from, stream and save: every position, velocity,
// angular velocity, force and torque finite, every particle within kRunawayLength of the box and
// slower than kRunawayLength a step (so that the next step's positions stay defined), and the
// probe's reaction finite. Sane parameters never make an unsound state from a sound one;
// when a numerical blow-up does, the run stops with a checkpoint of the last sound state (taken
// every kSoundSnapshotEvery steps) rather than step on, stream or save NaN (docs/dynamics.md).
#include "Construction.hpp"
#include "Model.hpp"
#include "Particles.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace bop::core {

inline constexpr double kRunawayLength = 1e6;          // how far beyond the box a particle may be, length
inline constexpr long long kSoundSnapshotEvery = 100;  // steps between copies of the last sound state

// The bounds of a sound particle, and its share of the soundness sum: NaN where the particle is
// out of bounds or too fast, else a sum of its velocity, angular velocity, force and torque,
// which a NaN or infinity makes so. A state is sound where the probe's reaction plus the sum
// over the particles is finite.
struct SoundBounds {
    Eigen::Array3d lo, hi;
    double maxSpeed2;  // (length / time)^2
    explicit SoundBounds(const Model& m)
        : lo(m.box.lo.array() - kRunawayLength),
          hi(m.box.hi.array() + kRunawayLength),
          maxSpeed2(std::pow(kRunawayLength / m.integration.dt, 2)) {}
    bool inside(const Eigen::Vector3d& x) const {
        return (x.array() >= lo).all() && (x.array() <= hi).all();
    }  // false for NaN
    bool slow(const Eigen::Vector3d& v) const { return v.squaredNorm() <= maxSpeed2; }
    double term(const Particles& p, std::size_t i) const {
        if (!(inside(p.pos[i]) && slow(p.vel[i]))) return std::nan("");
        return p.vel[i].sum() + p.omega[i].sum() + p.force[i].sum() + p.torque[i].sum();
    }
};

// Whether a state whose particles' SoundBounds terms sum to `terms` is sound.
inline bool soundSum(const Eigen::Vector3d& probeReaction, double terms) {
    return std::isfinite(probeReaction.sum() + terms);
}
// One pass over the particles, without a branch per particle.
bool sound(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction);
// What is wrong with a state, the first thing found.
struct Unsoundness {
    enum What : int {
        None = 0,
        Position,
        Runaway,
        Velocity,
        Speed,
        AngularVelocity,
        Force,
        Torque,
        ProbeReaction,
        Sum
    };
    What what = None;
    std::uint64_t id = 0;  // the particle's id (Position .. Torque)
    int species = 0;
    // "particle 123 (species 2): velocity not finite"; empty for None.
    std::string text() const;
};
Unsoundness findUnsound(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction);
inline std::string unsoundness(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction) {
    return findUnsound(model, p, probeReaction).text();
}

// Thrown by a step that ends in an unsound state (by every rank of a decomposed run at once).
class UnsoundState : public std::runtime_error {
public:
    UnsoundState(long long step, const std::string& what)
        : std::runtime_error("the state after step " + std::to_string(step) + " is not sound: " + what), step_(step) {}
    long long step() const { return step_; }

private:
    long long step_;
};

// A copy of a sound state: what a checkpoint of it needs.
struct SoundSnapshot {
    Particles particles;
    Construction construction;
    long long step = 0;
};

}  // namespace bop::core
