#pragma once
// The volume a bag's surface particles enclose, measured on a voxel lattice (the ejection
// fraction "from the particles", paper §5.2). Each surface particle stands for the surface
// voxel it sits in, so its sheet is the middle of a shell one voxel thick: a voxel centre c
// near the sheet (within `reach` of a surface particle) is inside when (c - p)·n < h/2 for its
// nearest particle p with outward normal n. Voxels farther from the sheet are outside when a
// path of voxels not inside joins them to the lattice's border (6-connected), inside otherwise.
// A hole in the sheet wider than about twice `reach` lets the outside flood in.
#include "bop/common/Volume.hpp"

#include <Eigen/Core>

#include <vector>

namespace bop::core {

// Lattice: `dims` voxels of edge h (length units), the corner of voxel (0,0,0) at the origin.
// Returns the number of voxels inside.
double filledVoxels(const Dims& dims, double h, const std::vector<Eigen::Vector3d>& pos,
                    const std::vector<Eigen::Vector3d>& normal, double reach);

}  // namespace bop::core
