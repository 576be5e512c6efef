#pragma once
// The messages ranks send each other (MpiExchange.hpp), one record type per kind and one tag
// enum per plan. Records travel as arrays of doubles (ids bit for bit, core/ParticleRecords.hpp);
// their layout is written here once, next to the struct. Point-to-point messages of a plan along
// axis a carry tag(plan tag, a); every plan runs on the run's own duplicated communicator
// (Comm.hpp), so no other code's messages can match them.
#include "core/ParticleRecords.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace bop::parallel {

// Point-to-point tags, per plan: the message to the lower and to the upper neighbour.
enum class MigrationTag : int { ToLower = 100, ToUpper = 102 };
enum class HaloBuildTag : int { ToLower = 200, ToUpper = 202 };
enum class HaloRefreshTag : int { ToLower = 300, ToUpper = 302 };
template <class Tag>
int tag(Tag t, int axis) {
    return int(t) + 4 * axis;
}

// A ghost as a halo build sends it: position (shifted across a periodic seam), normal, species, id.
struct GhostRecord {
    static constexpr std::size_t kFields = 8;
    Eigen::Vector3d pos, normal;
    int species = 0;
    std::uint64_t id = 0;
    void appendTo(std::vector<double>& out) const {
        out.insert(out.end(),
                   {pos.x(), pos.y(), pos.z(), normal.x(), normal.y(), normal.z(), double(species), core::idBits(id)});
    }
    static GhostRecord at(const double* v) {
        return {Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Vector3d(v[3], v[4], v[5]), int(v[6]), core::idOf(v[7])};
    }
};

// A ghost again along the same plan: position and normal.
struct GhostRefresh {
    static constexpr std::size_t kFields = 6;
    static void write(double* o, const Eigen::Vector3d& pos, const Eigen::Vector3d& normal) {
        o[0] = pos.x(), o[1] = pos.y(), o[2] = pos.z(), o[3] = normal.x(), o[4] = normal.y(), o[5] = normal.z();
    }
};

// A migrating particle: core::packParticle's record (core::kParticleRecord values).

}  // namespace bop::parallel
