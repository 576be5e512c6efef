#pragma once
// Particles as flat records of doubles, for what crosses between processes: ids and other 64-bit
// integers bit for bit, whole particles when they migrate or are gathered. The field order is
// the record's layout; every reader and writer goes through these functions.
#include "Particles.hpp"

#include <cstdint>
#include <cstring>
#include <vector>

namespace bop::core {

inline double idBits(std::uint64_t id) {
    double d;
    std::memcpy(&d, &id, sizeof d);
    return d;
}
inline std::uint64_t idOf(double d) {
    std::uint64_t id;
    std::memcpy(&id, &d, sizeof id);
    return id;
}

// A particle that moves to another process: position 3, velocity 3, orientation 4 (w x y z),
// angular velocity 3, species, id.
inline constexpr int kParticleRecord = 15;
// The same with its force 3 and torque 3 (gathered snapshots).
inline constexpr int kParticleWithForcesRecord = kParticleRecord + 6;

inline void packParticle(const Particles& p, std::size_t i, std::vector<double>& out) {
    const auto& q = p.q[i];
    out.insert(out.end(),
               {p.pos[i].x(), p.pos[i].y(), p.pos[i].z(), p.vel[i].x(), p.vel[i].y(), p.vel[i].z(), q.w(), q.x(), q.y(),
                q.z(), p.omega[i].x(), p.omega[i].y(), p.omega[i].z(), double(p.species[i]), idBits(p.id[i])});
}

// Appends the particle of one record (kParticleRecord values at v).
inline void unpackParticle(const double* v, Particles& p) {
    const std::size_t i =
        p.add(Eigen::Vector3d(v[0], v[1], v[2]), int(v[13]), idOf(v[14]), Eigen::Quaterniond(v[6], v[7], v[8], v[9]));
    p.q[i] = Eigen::Quaterniond(v[6], v[7], v[8], v[9]);  // bit for bit, not renormalised
    p.normal[i] = p.q[i] * Eigen::Vector3d::UnitZ();
    p.vel[i] = Eigen::Vector3d(v[3], v[4], v[5]);
    p.omega[i] = Eigen::Vector3d(v[10], v[11], v[12]);
}

inline void unpackParticles(const std::vector<double>& in, Particles& p) {
    for (std::size_t k = 0; k + kParticleRecord <= in.size(); k += kParticleRecord) unpackParticle(&in[k], p);
}

}  // namespace bop::core
