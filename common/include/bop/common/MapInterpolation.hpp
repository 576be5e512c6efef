#pragma once
// How the gradient map's force is read between voxel centres (docs/physics.md §4.5): the scene
// chooses it ([shape] interpolation), the force field reads it (core/MapField.hpp).
#include <cstdint>

namespace bop {

// Nearest: the rule of the particle's voxel (the paper's); Trilinear: the rules of the 8 voxels
// around it blended; Mixed: nearest for surface particles, trilinear for volume particles.
enum class Interpolation : std::uint8_t { Mixed, Trilinear, Nearest };

}  // namespace bop
