#pragma once
// Voxelization of a closed triangle mesh into an object mask by ray parity.
#include "TriangleMesh.hpp"
#include "bop/common/Volume.hpp"

namespace bop::shape {

// Sets out (resized to grid.dims) to 1 where the voxel centre grid.centreMm(i, j, k) lies inside
// the closed mesh (vertices in mm, same frame as grid.originMm) and 0 elsewhere.
// Each centre is classified by three axis rays (+x, +y, +z) with a 2-of-3 majority vote, so a
// ray grazing an edge or vertex does not spoil a voxel. A centre exactly on the surface counts
// as if moved by a tiny positive amount along each axis: for an axis-aligned box [a, b] the
// centres with a <= c < b are inside. Cost about O(triangles x rows covered + voxels).
// The mesh should be closed (see requireClosed); with holes the result is undefined but safe.
// Throws bop::Error("voxelizeMesh", ...) for a triangle index out of range, a non-finite vertex,
// negative dimensions or a voxel size that is not finite and > 0.
void voxelizeMesh(const TriangleMesh& mesh, const VoxelGrid& grid, Mask& out);

}  // namespace bop::shape
