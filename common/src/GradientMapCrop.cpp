#include "bop/common/GradientMapCrop.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop {

VoxelWindow windowAround(const Dims& whole, double h, const Eigen::Vector3d& regionLo, const Eigen::Vector3d& regionHi,
                         double margin) {
    const Eigen::Vector3i n(whole.nx, whole.ny, whole.nz);
    VoxelWindow w;
    for (int a = 0; a < 3; ++a) {
        // Clamp in floating point before converting: an open subdomain face may be far away.
        const double lo = std::clamp(std::floor((regionLo[a] - margin) / h), 0.0, double(n[a] - 1));
        const double hi = std::clamp(std::ceil((regionHi[a] + margin) / h), lo + 1, double(n[a]));
        w.lo[a] = int(lo);
        w.hi[a] = int(hi);
    }
    return w;
}

GradientMap cropGradientMap(const GradientMap& map, const VoxelWindow& window) {
    // map may itself be a window of the whole map (map.origin): the crop then holds part of it.
    const Dims& d = map.dims();
    const Dims cd = window.dims();
    const Eigen::Vector3i lo = window.lo - map.origin, hi = window.hi - map.origin;
    if ((lo.array() < 0).any() || hi.x() > d.nx || hi.y() > d.ny || hi.z() > d.nz || cd.nx < 1 || cd.ny < 1 ||
        cd.nz < 1)
        throw std::invalid_argument("cropGradientMap: window outside the map or empty");
    GradientMap out;
    out.grid = map.grid;
    out.grid.dims = cd;
    out.r0Voxels = map.r0Voxels;
    out.bagCount = map.bagCount;
    out.bagParent = map.bagParent;
    out.origin = window.lo;
    out.whole = map.wholeDims();
    out.occ.resize(cd.count());
    out.nearest.resize(cd.count());
    // Surface records the window names, kept in whole-map order so the crop reads like a whole map.
    std::vector<std::uint32_t> named;
    for (int k = 0; k < cd.nz; ++k)
        for (int j = 0; j < cd.ny; ++j)
            for (int i = 0; i < cd.nx; ++i) {
                const std::size_t src = d.index(i + lo.x(), j + lo.y(), k + lo.z());
                const std::size_t dst = cd.index(i, j, k);
                out.occ[dst] = map.occ[src];
                out.nearest[dst] = map.nearest[src];
                // neighbours mostly name the same record: a run of one is pushed once
                if (named.empty() || named.back() != map.nearest[src]) named.push_back(map.nearest[src]);
            }
    if (map.surface.size() <= 8 * cd.count()) {  // a small map's records: marked, then numbered in order
        std::vector<std::uint32_t> renumber(map.surface.size(), 0);
        for (std::uint32_t s : named) renumber[s] = 1;
        for (std::size_t s = 0; s < map.surface.size(); ++s)
            if (renumber[s]) {
                renumber[s] = std::uint32_t(out.surface.size());
                out.surface.push_back(map.surface[s]);
            }
        for (auto& n : out.nearest) n = renumber[n];
        return out;
    }
    std::sort(named.begin(), named.end());
    named.erase(std::unique(named.begin(), named.end()), named.end());
    out.surface.reserve(named.size());
    for (std::uint32_t s : named) out.surface.push_back(map.surface[s]);
    for (auto& n : out.nearest) n = std::uint32_t(std::lower_bound(named.begin(), named.end(), n) - named.begin());
    return out;
}

std::size_t gradientMapBytes(const GradientMap& map) {
    return map.occ.size() * sizeof(map.occ[0]) + map.nearest.size() * sizeof(map.nearest[0]) +
           map.surface.size() * sizeof(SurfaceVoxel);
}

}  // namespace bop
