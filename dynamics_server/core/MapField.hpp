#pragma once
// Gradient-map force and torque rules (paper Figs. 3 and 4, §3.4; docs/physics.md §4.5–4.6) as the
// dynamics core calls them: (kind, species, position, normal) -> (force, torque).
//
// Simulation coordinates: the corner of voxel (0,0,0) is the origin and a voxel is
// h = voxelLength(r0Voxels) simulation length units wide (bop/common/Units.hpp).
// The returned force is the raw f^GM in simulation length units (a unit-stiffness spring, to be
// multiplied by the species weight alpha_f^GM); the torque is n_i x n(p) (dimensionless, times
// alpha_tau^GM).
//
// Between voxel centres, three choices (docs/shape-pipeline.md):
//  - Nearest: the paper's rule on the voxel containing the particle. A surface particle feels a
//    spring to its voxel's centre, which pins it to the layer of surface voxels (stable; spacing
//    quantised by the voxels).
//  - Trilinear: the rules of the 8 voxels around the particle, evaluated at the particle and
//    blended with trilinear weights: continuous everywhere, equal to the paper's rule at voxel
//    centres. For surface particles the in-voxel springs cancel inside the shell, which lets them
//    drift through shells two voxels deep; surfaces then overfill with births.
//  - Mixed (default): Nearest for surface particles, Trilinear for volume particles, whose
//    rules have no in-voxel spring, so their force is continuous.
// Outside the grid the nearest border voxel's rule is used plus a spring back to its centre.
#include "bop/common/GradientMap.hpp"
#include "bop/common/MapInterpolation.hpp"
#include "bop/common/Units.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <vector>

namespace bop::core {

enum class ParticleKind : std::uint8_t { Surface, Volume };
using bop::Interpolation;  // bop/common/MapInterpolation.hpp

struct MapSample {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();   // f^GM, simulation length units
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // tau^GM = n_i x n(p); zero for volume kind
    // Surface kind: the co-planar weight of the nearest surface of the voxel holding the particle
    // (clamped into the map; MapForces::curvatureWeight's), dimensionless; 1 for volume kind.
    float cpWeight = 1.0f;
};

class MapField {
public:
    MapField(const GradientMap& map, Interpolation interp = Interpolation::Mixed);

    // What a surface particle read from the map at its last sample: the voxel holding it and that
    // voxel's nearest surface's normal and co-planar weight. A sheet's particle stays in its
    // voxel for many steps, and the look-up behind these (the voxel's nearest surface, then its
    // record) is two dependent reads far apart in memory: the memo answers them while the
    // particle stays, with the same values. The values are the voxel's, whoever asks: a memo
    // needs no owner, only the same map.
    struct Memo {
        std::size_t voxel = ~std::size_t(0);  // this map's voxel index, none yet
        Eigen::Vector3f normal{0, 0, 1};
        float cpWeight = 1.0f;
    };

    double voxelSize() const { return h_; }  // h, simulation length units per voxel
    const GradientMap& map() const { return map_; }

    // position: simulation units; normal: unit normal of a surface particle (ignored for volume).
    // memo: a surface particle's memo (may be null), read and updated on the paths that look up
    // a single voxel's nearest surface (Nearest, and Mixed for surface particles).
    MapSample sample(ParticleKind kind, int species, const Eigen::Vector3d& position, const Eigen::Vector3d& normal,
                     Memo* memo = nullptr) const;

    // The per-voxel rule in voxel units for a particle at pVox (voxel coordinates, where the
    // centre of voxel (i,j,k) is (i+1/2, j+1/2, k+1/2)). Exposed for tests.
    Eigen::Vector3d ruleAtVoxel(std::size_t v, ParticleKind kind, int species, const Eigen::Vector3d& pVox) const;
    // Outward normal n(v) of the nearest surface (docs/physics.md §4.4).
    Eigen::Vector3d normalAtVoxel(std::size_t v) const;

private:
    // The rule at voxel v, whose coordinates in this map are c (known to every caller in the step,
    // so that no voxel index is divided back into coordinates there).
    Eigen::Vector3d rule(std::size_t v, const Eigen::Vector3i& c, ParticleKind kind, int species,
                         const Eigen::Vector3d& pVox) const;

    // This map's voxel holding q (this map's voxel coordinates), clamped into the map.
    std::size_t floorVoxel(const Eigen::Vector3d& q) const {
        const Dims& dm = map_.dims();
        const Eigen::Vector3i c = q.array().floor().cast<int>().matrix();
        return dm.index(std::min(c.x(), dm.nx - 1), std::min(c.y(), dm.ny - 1), std::min(c.z(), dm.nz - 1));
    }

    const GradientMap& map_;
    Interpolation interp_;
    double h_;
    std::vector<Eigen::Vector3i> surfaceAt_;  // per surface voxel of the map: its whole-map coordinates
};

}  // namespace bop::core
