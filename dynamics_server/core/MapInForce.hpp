#pragma once
// The gradient map in force at a step, beside the scene's constants (Model.hpp): this process's
// region of the box, its window of every keyframe's map, and the keyframe blend of the step's
// time (Keyframes.hpp). Simulation keeps it (SimulationMaps.cpp), moved with the region and the
// keyframes; a cut or a yield replaces the windows with their edited copies (SimulationCuts.cpp),
// and the patches it keeps edit the windows a moved region reads later.
#include "Keyframes.hpp"
#include "Model.hpp"
#include "bop/common/GradientMapCrop.hpp"

#include <memory>
#include <vector>

namespace bop::core {

struct MapInForce {
    Box region;               // this process's region of the box (the whole box at one process)
    bop::VoxelWindow window;  // the voxels of the whole map the windows hold
    std::vector<std::shared_ptr<const GradientMap>> frames;  // the window of every keyframe; none: no map
    KeyframeAt at;                                           // frame a blends into frame b by w

    // Frame a's window (null without a map): the map the forces and the construction read.
    const std::shared_ptr<const GradientMap>& map() const { return frames.empty() ? kNone : frames[std::size_t(at.a)]; }
    // Frame b's window, which the forces blend in by at.w.
    const std::shared_ptr<const GradientMap>& next() const {
        return frames.empty() ? kNone : frames[std::size_t(at.b)];
    }

private:
    static inline const std::shared_ptr<const GradientMap> kNone{};
};

// The whole box and the model's whole map, static (one process without keyframes; tests).
inline MapInForce wholeMapOf(const Model& model) {
    MapInForce m;
    m.region = model.box;
    if (model.map) {
        const Dims& d = model.map->wholeDims();
        m.window = {Eigen::Vector3i::Zero(), Eigen::Vector3i(d.nx, d.ny, d.nz)};
        m.frames = {model.map};
    }
    return m;
}

}  // namespace bop::core
