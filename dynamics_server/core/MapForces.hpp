#pragma once
// The gradient map's forces and torques (docs/physics.md §4.5-4.6): each particle
// pulled along the map's gradient, a surface particle turned towards its normal, with the
// weights of its species; between keyframes a blend of two maps. The map's co-planar curvature
// weights come from the same voxel, per particle, for the pair forces.
#include "ForceStats.hpp"
#include "Model.hpp"
#include "Particles.hpp"

#include <memory>

namespace bop::core {

class MapForces {
public:
    // Sets particles.force and .torque to the forces and torques of `map`, the map in force (zero
    // without one), the first forces of a step, and its wall virial in stats. curvature: whether
    // the pairs read curvatureWeights() (else not written).
    void set(const Model& model, const std::shared_ptr<const GradientMap>& map, Particles& particles, ForceStats& stats,
             bool curvature);

    // Keyframe blending: until set again, the forces are (1 - w) of the map in force plus w of
    // `next` (a map on the same grid; null or w = 0: the map in force alone).
    void setBlend(const std::shared_ptr<const GradientMap>& next, double w) {
        blendMap_ = w > 0 ? next : nullptr, blendW_ = w;
    }

    // Per particle, the co-planar curvature weight of the last add() (1 without a map).
    const std::vector<float>& curvatureWeights() const { return curvature_; }
    // The co-planar curvature weight of `map` at x (1 without a map or for volume species).
    static float curvatureWeight(const Model& model, const GradientMap* map, const Eigen::Vector3d& x, int species);

private:
    std::unique_ptr<MapField> field_;
    std::shared_ptr<const GradientMap> fieldMap_;       // field_'s map, held: a new map never takes its address
    std::unique_ptr<MapField> blendField_;              // of blendFieldMap_
    std::shared_ptr<const GradientMap> blendFieldMap_;  // held, as fieldMap_ is
    std::shared_ptr<const GradientMap> blendMap_;
    double blendW_ = 0;
    std::vector<float> curvature_;
    std::vector<MapField::Memo> memo_;  // per particle index (surface particles'), of field_'s map
};

}  // namespace bop::core
