#pragma once
// Digital topology of a voxel object (26-connected object, 6-connected background): a voxel is a
// simple point when moving it between object and background changes neither, so no piece is cut
// off or joined, no tunnel or cavity opened or closed (Bertrand & Malandain 1994: one object
// component in its 26-neighbourhood and one background component 6-adjacent to it in its
// 18-neighbourhood). Whether a voxel is simple depends on its neighbours only, not on itself.
#include <array>

namespace bop::shape {

// Index of the neighbour at offset (dx, dy, dz), each in {-1, 0, 1}; 13 is the voxel itself.
constexpr int neighbourIndex(int dx, int dy, int dz) {
    return (dz + 1) * 9 + (dy + 1) * 3 + (dx + 1);
}

// object[neighbourIndex(dx, dy, dz)]: whether that neighbour is object; object[13] is ignored.
bool isSimplePoint(const std::array<bool, 27>& object);

}  // namespace bop::shape
