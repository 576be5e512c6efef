#pragma once
// Particles as records (Exchange.hpp) for what crosses between processes: a whole particle when
// it migrates to another process or is gathered, with its forces for snapshots. Every field is
// declared once here; writers and readers go through of() and appendTo().
#include "Particles.hpp"

#include <cstdint>

namespace bop::core {

// A particle that moves to another process.
struct ParticleRecord {
    Eigen::Vector3d pos, vel;  // length, length / time
    double q[4];               // orientation w, x, y, z (bit for bit, not renormalised)
    Eigen::Vector3d omega;     // rad / time
    std::uint64_t id = 0;
    std::int32_t species = 0;

    static ParticleRecord of(const Particles& p, std::size_t i) {
        return {p.pos[i],   p.vel[i], {p.q[i].w(), p.q[i].x(), p.q[i].y(), p.q[i].z()},
                p.omega[i], p.id[i],  p.species[i]};
    }
    void appendTo(Particles& p) const {
        const Eigen::Quaterniond orientation(q[0], q[1], q[2], q[3]);
        const std::size_t i = p.add(pos, species, id, orientation);
        p.q[i] = orientation;
        p.normal[i] = orientation * Eigen::Vector3d::UnitZ();
        p.vel[i] = vel;
        p.omega[i] = omega;
    }
};

// The same with its force and torque (gathered snapshots).
struct ParticleWithForces {
    ParticleRecord particle;
    Eigen::Vector3d force, torque;

    static ParticleWithForces of(const Particles& p, std::size_t i) {
        return {ParticleRecord::of(p, i), p.force[i], p.torque[i]};
    }
    void appendTo(Particles& p) const {
        particle.appendTo(p);
        p.force.back() = force;
        p.torque.back() = torque;
    }
};

}  // namespace bop::core
