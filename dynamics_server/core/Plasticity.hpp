#pragma once
// Lasting deformation (docs/physics.md §9.4): a dent held long enough, or pressed deep enough,
// becomes the bag's rest shape. Every `everySteps` each process finds the voxels of its region
// that lie in a bag, within bandR0 of its surface, and in front of every particle (below); the
// processes gather them by voxel, so that any rank count decides alike. A dent is a change: only
// a voxel that was not in front at the check before starts one (the first check only looks). A
// voxel in front for holdTime without a break since, or in front deeper than yieldDepthR0 below
// the surface, yields: it leaves its bag (bop::removalPatch), so that the map's surface is where
// the particles now are and nothing pulls them back. The particles stay. Off by default. A bonded
// bag's bonds keep their rest lengths, and so their shape: plasticity is for the bags the map
// alone holds.
#include "bop/common/GradientMapCrop.hpp"

#include <cstdint>
#include <vector>

namespace bop::core {

struct PlasticityParams {
    bool on = false;
    double holdTime = 0;        // a dent held this long yields, simulation time units (0: only by depth)
    double yieldDepthR0 = 0;    // a dent this deep below the surface yields at once, r0 (0: only by time)
    double bandR0 = 3;          // dents are looked for this far below the surface, r0
    long long everySteps = 10;  // steps between checks
};

// A voxel lies in front of the particles (outside the bag's present shape) when no particle lies in
// the cylinder looking out from it along its surface's normal: of radius kAcrossR0, from
// kBehindR0 behind it to kAheadR0 in front, multiples of r0. A sheet at rest covers every point of its
// plane within r0 / sqrt 3 of a particle, and lies half a voxel inside its surface voxels' faces.
inline constexpr double kAcrossR0 = 0.8, kBehindR0 = 0.25, kAheadR0 = 2.0;

}  // namespace bop::core
