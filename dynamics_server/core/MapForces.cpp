#include "MapForces.hpp"

#include "Threads.hpp"

namespace bop::core {

float MapForces::curvatureWeight(const Model& model, const GradientMap* map, const Eigen::Vector3d& x, int species) {
    if (!map || !model.isSurface(species)) return 1.0f;
    const double h = voxelLength(map->r0Voxels);
    return map->nearestSurface(map->voxelAt((x / h).array().floor().cast<int>().matrix())).cpWeight;
}

void MapForces::set(const Model& model, const std::shared_ptr<const GradientMap>& map, Particles& p, ForceStats& stats,
                    bool curvature) {
    if (curvature) curvature_.assign(p.size(), 1.0f);
    if (!map) {
        forEachIndex(p.size(), [&](std::size_t i) {
            p.force[i].setZero();
            p.torque[i].setZero();
        });
        return;
    }
    if (fieldMap_ != map) {
        field_ = std::make_unique<MapField>(*map, model.interpolation);
        fieldMap_ = map;
        memo_.clear();  // voxels of the old map
    }
    memo_.resize(p.size());
    if (blendMap_ && blendFieldMap_ != blendMap_) {
        blendField_ = std::make_unique<MapField>(*blendMap_, model.interpolation);  // the map held: never a freed one's
        blendFieldMap_ = blendMap_;
    }
    const double w = blendMap_ ? blendW_ : 0.0;
    const Dims& whole = map->wholeDims();
    const Eigen::Vector3d centre = 0.5 * Eigen::Vector3d(whole.nx, whole.ny, whole.nz) * field_->voxelSize();
    stats.wallVirial = sumIndex(p.size(), [&](std::size_t i) {  // each particle on its own: on the threads
        const Species& sp = model.species[p.species[i]];
        // A memo by index: after a sort or a migration it may hold another particle's voxel, whose
        // values are still that voxel's.
        MapSample g = field_->sample(sp.kind, p.species[i], p.pos[i], p.normal[i],
                                     sp.kind == ParticleKind::Surface ? &memo_[i] : nullptr);
        if (w > 0) {  // keyframes: on the way to the next frame's shape
            const MapSample n = blendField_->sample(sp.kind, p.species[i], p.pos[i], p.normal[i]);
            g.force = (1 - w) * g.force + w * n.force;
            g.torque = (1 - w) * g.torque + w * n.torque;
        }
        p.force[i] = sp.alphaForceGm * g.force;
        p.torque[i].setZero();
        if (sp.kind == ParticleKind::Surface) {
            p.torque[i] = sp.alphaTorqueGm * g.torque;
            if (curvature) curvature_[i] = g.cpWeight;  // curvatureWeight(), from the same voxel
            return 0.0;
        }
        return (p.pos[i] - centre).dot(sp.alphaForceGm * g.force);
    });
}

}  // namespace bop::core
