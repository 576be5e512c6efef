#pragma once
// Normals and curvature of the static surface at every surface voxel, from Gaussian-derivative
// filters of the smoothed "outside" indicator (Thirion & Gourdon; docs/physics.md §4.4, §5), and the
// co-planar weight map derived from the curvature (§5.3).
#include "BagLayout.hpp"
#include "bop/common/GradientMap.hpp"

#include <string>

namespace bop::shape {

enum class CpWeightForm { Linear, Quadratic };  // w = 1/(1 + c k r0)  or  1/(1 + (c k r0)^2)

struct SurfaceGeometryParams {
    double sigmaVoxels = 2.0;  // Gaussian width of the smoothing, voxels (>= 1.5 recommended)
    double cpWeightC = 4.0;    // c in the co-planar weight, dimensionless
    CpWeightForm cpWeightForm = CpWeightForm::Linear;
};

// Fills normal, curvatures and cpWeight of map.surface. For the surface of bag k the indicator
// is "the voxel lies outside bag k" (neither in it nor in a bag inside it): a bag touching
// another has its own normals along the faces they share.
void computeSurfaceGeometry(const BagLayout& bags, const SurfaceGeometryParams& p, GradientMap& map);

// The co-planar weight for a curvature kappa (1/voxel) and r0 (voxels).
float cpWeight(double kappa, double r0Voxels, const SurfaceGeometryParams& p);

}  // namespace bop::shape
