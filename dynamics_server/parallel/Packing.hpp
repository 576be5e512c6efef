#pragma once
// What the decomposed run's messages carry, as arrays of doubles: ids and other 64-bit
// integers bit for bit, and whole particles when they migrate or are gathered.
#include "core/Particles.hpp"

#include <cstdint>
#include <cstring>
#include <vector>

namespace bop::parallel {

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

constexpr int kMigrateFields = 15;  // pos 3, vel 3, q 4, omega 3, species, id

inline void packParticle(const core::Particles& p, std::size_t i, std::vector<double>& out) {
    const auto& q = p.q[i];
    out.insert(out.end(), {p.pos[i].x(), p.pos[i].y(), p.pos[i].z(), p.vel[i].x(), p.vel[i].y(), p.vel[i].z(), q.w(),
                           q.x(), q.y(), q.z(), p.omega[i].x(), p.omega[i].y(), p.omega[i].z(), double(p.species[i]),
                           idBits(p.id[i])});
}

inline void unpackParticles(const std::vector<double>& in, core::Particles& p) {
    for (std::size_t k = 0; k + kMigrateFields <= in.size(); k += kMigrateFields) {
        const double* v = &in[k];
        const std::size_t i = p.add(Eigen::Vector3d(v[0], v[1], v[2]), int(v[13]), idOf(v[14]),
                                    Eigen::Quaterniond(v[6], v[7], v[8], v[9]));
        p.q[i] = Eigen::Quaterniond(v[6], v[7], v[8], v[9]);  // bit for bit, not renormalised
        p.normal[i] = p.q[i] * Eigen::Vector3d::UnitZ();
        p.vel[i] = Eigen::Vector3d(v[3], v[4], v[5]);
        p.omega[i] = Eigen::Vector3d(v[10], v[11], v[12]);
    }
}

}  // namespace bop::parallel
