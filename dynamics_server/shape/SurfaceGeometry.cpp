#include "SurfaceGeometry.hpp"

#include <vector>

namespace bop::shape {

void computeSurfaceGeometry(const BagLayout& bags, const SurfaceGeometryParams& p, GradientMap& map) {
    const SurfaceKernels K(p.sigmaVoxels);
    const long long n = (long long)map.surface.size();
    const Dims& dm = bags.bag.dims;
#pragma omp parallel
    {
        std::vector<double> scratch;
#pragma omp for schedule(dynamic, 256)
        for (long long s = 0; s < n; ++s) {
            SurfaceVoxel& sv = map.surface[std::size_t(s)];
            const Eigen::Vector3i c = map.dims().coords(sv.voxel);
            const int level = bagOfSpecies(sv.species);  // bag of this surface
            // chi = 1 outside bag `level` and beyond the grid
            auto outside = [&](int x, int y, int z) {
                return !dm.contains(x, y, z) || !bags.within(bags.bag(x, y, z), level);
            };
            const IndicatorDerivatives f = indicatorDerivatives(outside, c.x(), c.y(), c.z(), K, scratch);
            setSurfaceGeometry(sv, f, faceNormal(outside, c.x(), c.y(), c.z()), map.r0Voxels, p);
        }
    }
}

}  // namespace bop::shape
