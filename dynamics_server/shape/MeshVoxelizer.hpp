#pragma once
// Voxelization of a closed triangle mesh into an object mask by signed ray crossings.
#include "TriangleMesh.hpp"
#include "bop/common/Volume.hpp"

namespace bop::shape {

// Sets out (resized to grid.dims) to 1 where the voxel centre grid.centreMm(i, j, k) lies inside
// the closed mesh (vertices in mm, same frame as grid.originMm) and 0 elsewhere.
// Along each axis ray (+x, +y, +z) a centre's winding number is the sum of the crossings ahead
// of it, +1 where the ray leaves through an outward face and -1 where it enters; the centre is
// inside that ray when it is 1 or more (parts of a mesh that overlap count once). The three rays
// vote 2 of 3, so a ray grazing an edge or vertex does not spoil a voxel. A centre exactly on the surface counts
// as if moved by a tiny positive amount along each axis: for an axis-aligned box [a, b] the
// centres with a <= c < b are inside. Cost about O(triangles x rows covered + voxels).
// The mesh should be closed (MeshRepair::closed); with holes the result is undefined but safe
// (WindingNumber.hpp voxelizes those).
// Throws bop::Error("voxelizeMesh", ...) for a triangle index out of range, a non-finite vertex,
// negative dimensions or a voxel size that is not finite and > 0.
void voxelizeMesh(const TriangleMesh& mesh, const VoxelGrid& grid, Mask& out);

}  // namespace bop::shape
