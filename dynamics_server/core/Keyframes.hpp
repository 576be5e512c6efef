#pragma once
// Gradient maps as keyframes (paper §5.2): a bag whose shape changes by cycling through a
// sequence of maps, one per gated image frame. Before `startTime` the first frame f holds; from
// then on frame (f + k) mod frames is in force from start + k·duration; with blending, the shape forces move linearly
// from one frame's map to the next's across each frame's interval, so they never jump. The schedule depends on the
// simulation time alone, so every rank of a decomposed run picks the same frames.
#include "bop/common/GradientMap.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bop::core {

struct KeyframeAt {
    int a = 0, b = 0;                       // frame in force and the frame it blends towards
    double w = 0;                           // weight of b in [0, 1): force = (1 - w) f_a + w f_b
    double phase() const { return a + w; }  // frame number with its fraction, for reports
};

struct KeyframeSchedule {
    int frames = 1;              // maps in the sequence (1: a static shape)
    double frameDuration = 1.0;  // time each frame is in force, simulation time units
    double startTime = 0;        // cycling starts here; before it firstFrame holds (construction)
    int firstFrame = 0;          // the frame held before startTime and the cycle's first
    bool blend = true;           // blend each frame into the next across its interval

    bool animated() const { return frames > 1; }
    double period() const { return frames * frameDuration; }  // one cycle, simulation time units

    KeyframeAt at(double time) const {
        if (!animated() || time < startTime) return {firstFrame, firstFrame, 0};
        // The small margin keeps a frame boundary that falls on a step (t = start + k·duration
        // up to rounding) on the side of the new frame.
        const double phase = (time - startTime) / frameDuration + 1e-9;
        const double whole = std::floor(phase);
        const int a = int((firstFrame + static_cast<long long>(whole)) % frames);
        return {a, (a + 1) % frames, blend ? std::max(0.0, phase - whole - 1e-9) : 0.0};
    }
};

// Voxel counts of one map: every voxel of a bag (the cavity) and the voxels of volume species
// (where the blood is, paper §5.2's V), both within a box of simulation coordinates (voxel
// centres in [lo, hi), so that the subdomains of a decomposed run count each voxel once).
struct MapVolume {
    double bagVoxels = 0, volumeVoxels = 0;
};
MapVolume countMapVolume(const GradientMap& map, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

// The blend of per-frame values at `at`.
inline double blendFrames(const std::vector<double>& perFrame, const KeyframeAt& at) {
    if (perFrame.empty()) return 0;
    return (1 - at.w) * perFrame[std::size_t(at.a)] + at.w * perFrame[std::size_t(at.b)];
}

}  // namespace bop::core
