#include "Plasticity.hpp"

#include <climits>

namespace bop::core {

bop::VoxelWindow boxOfVoxels(const std::vector<std::uint64_t>& voxels, const Dims& whole) {
    bop::VoxelWindow w{Eigen::Vector3i::Constant(INT_MAX), Eigen::Vector3i::Constant(INT_MIN)};
    for (std::uint64_t v : voxels) {
        const Eigen::Vector3i c = whole.coords(std::size_t(v));
        w.lo = w.lo.cwiseMin(c);
        w.hi = w.hi.cwiseMax(c + Eigen::Vector3i::Ones());
    }
    if (voxels.empty()) w.lo = w.hi = Eigen::Vector3i::Zero();
    return w;
}

}  // namespace bop::core
