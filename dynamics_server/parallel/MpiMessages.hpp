#pragma once
// The messages ranks send each other (MpiExchange.hpp), one record type per kind (core/Records.hpp:
// fields declared once, sent as their bytes) and one tag enum per plan. Point-to-point messages
// of a plan along axis a carry tag(plan tag, a); every plan runs on the run's own duplicated
// communicator (Comm.hpp), so no other code's messages can match them.
#include "core/ParticleRecords.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace bop::parallel {

// Point-to-point tags, per plan: the message to the lower and to the upper neighbour.
enum class MigrationTag : int { ToLower = 100, ToUpper = 102 };
enum class HaloBuildTag : int { ToLower = 200, ToUpper = 202 };
enum class HaloRefreshTag : int { ToLower = 300, ToUpper = 302 };
enum class GhostValueTag : int { ToLower = 400, ToUpper = 402 };
template <class Tag>
int tag(Tag t, int axis) {
    return int(t) + 4 * axis;
}

// A ghost as a halo build sends it: position (shifted across a periodic seam), normal, species, id.
struct GhostRecord {
    Eigen::Vector3d pos, normal;
    std::uint64_t id = 0;
    std::int32_t species = 0;
};

// A ghost again along the same plan: position and normal.
struct GhostRefresh {
    Eigen::Vector3d pos, normal;
};

// A value per ghost along the plan (a bonded particle's dilatation, core/Bonds.hpp).
struct GhostValue {
    double value = 0;
};

// A migrating particle: core::ParticleRecord.

}  // namespace bop::parallel
