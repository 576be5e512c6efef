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
    // Sets particles.force and .torque to the map's forces and torques (zero without a map), the
    // first forces of a step, and its wall virial in stats. curvature: whether the pairs read
    // curvatureWeights() (else not written).
    void set(const Model& model, Particles& particles, ForceStats& stats, bool curvature);

    // Keyframe blending: until set again, the forces are (1 - w) of the model's map plus w of
    // `next` (a map on the same grid; null or w = 0: the model's map alone).
    void setBlend(const GradientMap* next, double w) {
        if (next != blendFieldMap_) blendField_.reset(), blendFieldMap_ = nullptr;  // never a field of a freed map
        blendMap_ = w > 0 ? next : nullptr, blendW_ = w;
    }

    // Per particle, the co-planar curvature weight of the last add() (1 without a map).
    const std::vector<float>& curvatureWeights() const { return curvature_; }
    // The co-planar curvature weight at x (1 without a map or for volume species).
    static float curvatureWeight(const Model& model, const Eigen::Vector3d& x, int species);

private:
    std::unique_ptr<GmField> field_;
    std::shared_ptr<const GradientMap> fieldMap_;  // field_'s map, held: a new map never takes its address
    std::unique_ptr<GmField> blendField_;          // of blendMap_
    const GradientMap* blendFieldMap_ = nullptr;
    const GradientMap* blendMap_ = nullptr;
    double blendW_ = 0;
    std::vector<float> curvature_;
    std::vector<GmField::Memo> memo_;  // per particle index (surface particles'), of field_'s map
};

}  // namespace bop::core
