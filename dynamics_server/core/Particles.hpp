#pragma once
// Particle state in struct-of-arrays form: one array per field, index i is one particle.
// Lengths in simulation units (r0 = sqrt(3)), mass 1, time in simulation time units.
// Orientation fields are meaningful for surface (oriented) particles; volume particles keep
// the identity quaternion and zero angular velocity.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace bop::core {

struct Particles {
    std::vector<Eigen::Vector3d> pos;     // position
    std::vector<Eigen::Vector3d> vel;     // velocity
    std::vector<Eigen::Quaterniond> q;    // orientation (unit quaternion, w x y z)
    std::vector<Eigen::Vector3d> omega;   // angular velocity, space frame
    std::vector<Eigen::Vector3d> normal;  // cached n = R(q) e_z (recomputed after each rotation)
    std::vector<Eigen::Vector3d> force;   // total force of the last evaluation (without drag)
    std::vector<Eigen::Vector3d> torque;  // total torque of the last evaluation (without drag)
    std::vector<std::uint8_t> species;    // species number (1-based, see the scene's species table)
    std::vector<std::uint64_t> id;        // global id, unique for the particle's lifetime
    std::uint64_t revision = 0;           // counts add/remove/resize (neighbour lists rebuild on change)

    std::size_t size() const { return pos.size(); }

    // Appends a particle at rest; q is the orientation (identity for volume particles).
    std::size_t add(const Eigen::Vector3d& p, int speciesNumber, std::uint64_t globalId,
                    const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity()) {
        pos.push_back(p);
        vel.push_back(Eigen::Vector3d::Zero());
        q.push_back(orientation.normalized());
        omega.push_back(Eigen::Vector3d::Zero());
        normal.push_back(q.back() * Eigen::Vector3d::UnitZ());
        force.push_back(Eigen::Vector3d::Zero());
        torque.push_back(Eigen::Vector3d::Zero());
        species.push_back(std::uint8_t(speciesNumber));
        id.push_back(globalId);
        ++revision;
        return pos.size() - 1;
    }

    // Removes the particles whose flag is set, keeping the order of the others.
    void removeIf(const std::vector<char>& flag) {
        std::size_t w = 0;
        for (std::size_t i = 0; i < size(); ++i) {
            if (flag[i]) continue;
            if (w != i) {
                pos[w] = pos[i];
                vel[w] = vel[i];
                q[w] = q[i];
                omega[w] = omega[i];
                normal[w] = normal[i];
                force[w] = force[i];
                torque[w] = torque[i];
                species[w] = species[i];
                id[w] = id[i];
            }
            ++w;
        }
        resize(w);
    }

    void resize(std::size_t n) {
        ++revision;
        pos.resize(n);
        vel.resize(n);
        q.resize(n);
        omega.resize(n);
        normal.resize(n);
        force.resize(n);
        torque.resize(n);
        species.resize(n);
        id.resize(n);
    }
};

}  // namespace bop::core
