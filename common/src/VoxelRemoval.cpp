// removalPatch for a list of voxels (bop/common/GradientMapEdit.hpp): the yields of plasticity,
// on the server and in the haptic client's copy.
#include "bop/common/GradientMapEdit.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <string>

namespace bop {

VoxelWindow boxOfVoxels(const std::vector<std::uint64_t>& voxels, const Dims& whole) {
    VoxelWindow w{Eigen::Vector3i::Constant(INT_MAX), Eigen::Vector3i::Constant(INT_MIN)};
    for (std::uint64_t v : voxels) {
        const Eigen::Vector3i c = whole.coords(std::size_t(v));
        w.lo = w.lo.cwiseMin(c);
        w.hi = w.hi.cwiseMax(c + Eigen::Vector3i::Ones());
    }
    if (voxels.empty()) w.lo = w.hi = Eigen::Vector3i::Zero();
    return w;
}

MapPatch voxelsPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels,
                     const std::vector<std::uint64_t>& voxels, const SurfaceGeometryParams& p) {
    if (!std::is_sorted(voxels.begin(), voxels.end()))
        throw std::invalid_argument("voxels to remove: not in increasing order");
    if (!voxels.empty() && voxels.back() >= whole.count())
        throw std::invalid_argument("voxels to remove: index " + std::to_string(voxels.back()) + " beyond the map's " +
                                    std::to_string(whole.count()) + " voxels");
    if (voxels.empty()) return {};
    return removalPatch(
        read, whole, r0Voxels, boxOfVoxels(voxels, whole),
        [&](const Eigen::Vector3i& c) {
            return std::binary_search(voxels.begin(), voxels.end(), std::uint64_t(whole.index(c.x(), c.y(), c.z())));
        },
        p);
}

}  // namespace bop
