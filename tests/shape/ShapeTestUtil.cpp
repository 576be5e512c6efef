#include "ShapeTestUtil.hpp"

namespace bop::test {

Volume<std::uint8_t> depthFrom(const Dims& d, const std::vector<std::function<bool(const Eigen::Vector3d&)>>& inside) {
    Volume<std::uint8_t> depth(d, 0);
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const Eigen::Vector3d c(i + 0.5, j + 0.5, k + 0.5);
                std::uint8_t n = 0;
                while (n < inside.size() && inside[n](c)) ++n;
                depth(i, j, k) = n;
            }
    return depth;
}

GradientMap mapFrom(const Volume<std::uint8_t>& depth, double r0Voxels, double sigma) {
    VoxelGrid g;
    g.dims = depth.dims;
    SurfaceGeometryParams p;
    p.sigmaVoxels = sigma;
    return shape::buildGradientMap(g, depth, r0Voxels, p);
}

core::Model bagModel(const GradientMap& map) {
    core::Model m;
    m.species.assign(3, core::Species{});
    m.species[1].kind = core::ParticleKind::Surface;
    m.species[2].kind = core::ParticleKind::Volume;
    m.map = std::make_shared<GradientMap>(map);
    m.box.hi = Eigen::Vector3d(map.dims().nx, map.dims().ny, map.dims().nz) * voxelLength(map.r0Voxels);
    return m;
}

}  // namespace bop::test
