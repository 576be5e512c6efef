#include "SoundState.hpp"

#include <cmath>

namespace bop::core {
namespace {

struct Bounds {
    Eigen::Array3d lo, hi;
    explicit Bounds(const Model& m)
        : lo(m.box.lo.array() - kRunawayLength), hi(m.box.hi.array() + kRunawayLength) {}
    bool inside(const Eigen::Vector3d& x) const { return (x.array() >= lo).all() && (x.array() <= hi).all(); }  // false for NaN
};

}  // namespace

bool sound(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction) {
    const Bounds b(model);
    bool inside = true;
    double sum = probeReaction.sum();  // any NaN or infinity makes the sum so
    for (std::size_t i = 0; i < p.size(); ++i) {
        inside &= b.inside(p.pos[i]);
        sum += p.vel[i].sum() + p.omega[i].sum() + p.force[i].sum() + p.torque[i].sum();
    }
    return inside && std::isfinite(sum);
}

std::string unsoundness(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction) {
    if (sound(model, p, probeReaction)) return {};
    const Bounds b(model);
    const auto particle = [&](std::size_t i, const char* what) {
        return "particle " + std::to_string(p.id[i]) + " (species " + std::to_string(p.species[i]) + "): " + what;
    };
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!p.pos[i].allFinite()) return particle(i, "position not finite");
        if (!b.inside(p.pos[i])) return particle(i, "more than 1e6 length units beyond the box");
        if (!p.vel[i].allFinite()) return particle(i, "velocity not finite");
        if (!p.omega[i].allFinite()) return particle(i, "angular velocity not finite");
        if (!p.force[i].allFinite()) return particle(i, "force not finite");
        if (!p.torque[i].allFinite()) return particle(i, "torque not finite");
    }
    if (!probeReaction.allFinite()) return "the probe's reaction force not finite";
    return "a sum of velocities, forces and torques beyond the double range";
}

}  // namespace bop::core
