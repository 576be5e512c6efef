#pragma once
// Normals and curvature of the static surface at every surface voxel, from Gaussian-derivative
// filters of the smoothed "outside" indicator (bop/common/SurfaceFilters.hpp; docs/physics.md
// §4.4, §5), and the co-planar weight map derived from the curvature (§5.3).
#include "BagLayout.hpp"
#include "bop/common/GradientMap.hpp"
#include "bop/common/SurfaceFilters.hpp"

namespace bop::shape {

// Fills normal, curvatures and cpWeight of map.surface. For the surface of bag k the indicator
// is "the voxel lies outside bag k" (neither in it nor in a bag inside it): a bag touching
// another has its own normals along the faces they share.
void computeSurfaceGeometry(const BagLayout& bags, const SurfaceGeometryParams& p, GradientMap& map);

}  // namespace bop::shape
