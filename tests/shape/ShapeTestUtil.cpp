#include "ShapeTestUtil.hpp"

#include <catch2/catch.hpp>

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

void requireSameMap(const GradientMap& edited, const GradientMap& truth) {
    REQUIRE(edited.occ == truth.occ);
    std::size_t distances = 0;
    for (std::size_t v = 0; v < truth.wholeDims().count(); ++v)
        distances += edited.delta(v).squaredNorm() == truth.delta(v).squaredNorm();
    REQUIRE(distances == truth.wholeDims().count());
    REQUIRE(edited.surface.size() == truth.surface.size());
    std::size_t same = 0;
    for (std::size_t s = 0; s < truth.surface.size(); ++s) {
        const SurfaceVoxel &a = edited.surface[s], &b = truth.surface[s];
        same += a.voxel == b.voxel && a.species == b.species && a.normal == b.normal &&
                a.meanCurvature == b.meanCurvature && a.gaussCurvature == b.gaussCurvature && a.kappa == b.kappa &&
                a.cpWeight == b.cpWeight;
    }
    REQUIRE(same == truth.surface.size());
}

}  // namespace bop::test
