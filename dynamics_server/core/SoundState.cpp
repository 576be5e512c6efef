#include "SoundState.hpp"

#include "Threads.hpp"

#include <cmath>

namespace bop::core {

bool sound(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction) {
    const SoundBounds b(model);
    // Any NaN or infinity makes the sum so, and so does a particle out of bounds (on the threads).
    return soundSum(probeReaction, sumIndex(p.size(), [&](std::size_t i) { return b.term(p, i); }));
}

std::string Unsoundness::text() const {
    static const char* const what[] = {"",
                                       "position not finite",
                                       "more than 1e6 length units beyond the box",
                                       "velocity not finite",
                                       "faster than 1e6 length units a step",
                                       "angular velocity not finite",
                                       "force not finite",
                                       "torque not finite",
                                       "the probe's reaction force not finite",
                                       "a sum of velocities, forces and torques beyond the double range"};
    if (this->what == None) return {};
    if (this->what >= ProbeReaction) return what[this->what];
    return "particle " + std::to_string(id) + " (species " + std::to_string(species) + "): " + what[this->what];
}

Unsoundness findUnsound(const Model& model, const Particles& p, const Eigen::Vector3d& probeReaction) {
    if (sound(model, p, probeReaction)) return {};
    const SoundBounds b(model);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto at = [&](Unsoundness::What w) { return Unsoundness{w, p.id[i], p.species[i]}; };
        if (!p.pos[i].allFinite()) return at(Unsoundness::Position);
        if (!b.inside(p.pos[i])) return at(Unsoundness::Runaway);
        if (!p.vel[i].allFinite()) return at(Unsoundness::Velocity);
        if (!b.slow(p.vel[i])) return at(Unsoundness::Speed);
        if (!p.omega[i].allFinite()) return at(Unsoundness::AngularVelocity);
        if (!p.force[i].allFinite()) return at(Unsoundness::Force);
        if (!p.torque[i].allFinite()) return at(Unsoundness::Torque);
    }
    if (!probeReaction.allFinite()) return {Unsoundness::ProbeReaction};
    return {Unsoundness::Sum};
}

}  // namespace bop::core
