#include "Keyframes.hpp"

#include "Potentials.hpp"

namespace bop::core {

MapVolume countMapVolume(const GradientMap& map, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    MapVolume out;
    const double h = voxelLength(map.r0Voxels);
    const Dims& d = map.dims();
    for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
            for (int x = 0; x < d.nx; ++x) {
                const Eigen::Vector3d c = (Eigen::Vector3i(x, y, z) + map.origin).cast<double>().array() + 0.5;
                const Eigen::Vector3d p = c * h;
                if ((p.array() < lo.array()).any() || (p.array() >= hi.array()).any()) continue;
                const int s = map.occ[d.index(x, y, z)];
                if (s == 0) continue;
                out.bagVoxels += 1;
                if (!isSurfaceSpecies(s)) out.volumeVoxels += 1;
            }
    return out;
}

}  // namespace bop::core
