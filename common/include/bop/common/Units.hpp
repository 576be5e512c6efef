#pragma once
// The units every component shares (docs/physics.md §0): lengths in simulation units, where the
// LJ form's equilibrium spacing is r0 = sqrt(3); a gradient map's voxel is r0 / r0Voxels long.
namespace bop {

inline constexpr double kR0 = 1.7320508075688772;  // r0 = sqrt(3), simulation length units

// The edge of a voxel of a map whose r0 spans r0Voxels voxels, simulation length units.
inline constexpr double voxelLength(double r0Voxels) {
    return kR0 / r0Voxels;
}

}  // namespace bop
