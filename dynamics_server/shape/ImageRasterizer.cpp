#include "ImageRasterizer.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bop::shape {
namespace {

// For each grid index along one axis, the image index holding the grid voxel centre, or -1.
std::vector<int> axisLookup(int gridCount, double gridOrigin, double voxelMm, int imageCount, double imageOrigin,
                            double spacing) {
    std::vector<int> idx(std::size_t(std::max(gridCount, 0)), -1);
    for (int g = 0; g < gridCount; ++g) {
        const double c = gridOrigin + voxelMm * (g + 0.5);
        const double f = std::floor((c - imageOrigin) / spacing);
        if (f >= 0.0 && f < double(imageCount)) idx[std::size_t(g)] = int(f);
    }
    return idx;
}

}  // namespace

bool isSelected(float value, const ImageSelect& sel) {
    if (sel.mode == ImageSelect::Mode::Label)
        return std::any_of(sel.labels.begin(), sel.labels.end(), [&](double l) { return value == float(l); });
    return double(value) >= sel.threshold;
}

Eigen::AlignedBox3d imageBounds(const ScalarImage& img) {
    const Eigen::Vector3d n(img.dims.nx, img.dims.ny, img.dims.nz);
    return Eigen::AlignedBox3d(img.originMm, img.originMm + n.cwiseProduct(img.spacingMm));
}

void rasterizeImage(const ScalarImage& img, const ImageSelect& sel, const VoxelGrid& grid, Mask& out) {
    if (img.values.size() != img.dims.count())
        throw Error("rasterizeImage", "image holds " + std::to_string(img.values.size()) + " values, its dims need " +
                                          std::to_string(img.dims.count()));
    for (int a = 0; a < 3; ++a)
        if (!(img.spacingMm[a] > 0.0)) throw Error("rasterizeImage", "image spacing must be positive");
    if (!(grid.voxelMm > 0.0)) throw Error("rasterizeImage", "grid voxel size must be positive");

    out = Mask(grid.dims, 0);
    const Dims& g = grid.dims;
    const auto ix = axisLookup(g.nx, grid.originMm.x(), grid.voxelMm, img.dims.nx, img.originMm.x(), img.spacingMm.x());
    const auto iy = axisLookup(g.ny, grid.originMm.y(), grid.voxelMm, img.dims.ny, img.originMm.y(), img.spacingMm.y());
    const auto iz = axisLookup(g.nz, grid.originMm.z(), grid.voxelMm, img.dims.nz, img.originMm.z(), img.spacingMm.z());

    for (int k = 0; k < g.nz; ++k) {
        if (iz[std::size_t(k)] < 0) continue;
        for (int j = 0; j < g.ny; ++j) {
            if (iy[std::size_t(j)] < 0) continue;
            const std::size_t rowImg = img.dims.index(0, iy[std::size_t(j)], iz[std::size_t(k)]);
            const std::size_t rowOut = g.index(0, j, k);
            for (int i = 0; i < g.nx; ++i) {
                const int si = ix[std::size_t(i)];
                if (si >= 0 && isSelected(img.values[rowImg + std::size_t(si)], sel))
                    out.data[rowOut + std::size_t(i)] = 1;
            }
        }
    }
}

std::size_t countSelected(const ScalarImage& img, const ImageSelect& sel) {
    std::size_t n = 0;
    for (float v : img.values)
        if (isSelected(v, sel)) ++n;
    return n;
}

}  // namespace bop::shape
