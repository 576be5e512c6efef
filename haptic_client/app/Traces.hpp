#pragma once
// What bop-haptic writes (docs/haptics.md): the per-tick trace as CSV (device, proxy, forces,
// safety gain, feedback age, lateness), and for a poke the stiffness curve — the force felt
// against the depth past the surface, averaged in depth bins — as CSV and a PNG plot.
#include "control/ForceModel.hpp"
#include "control/RateLoop.hpp"

#include <fstream>
#include <string>
#include <vector>

namespace bop::haptic {

class TraceCsv {
public:
    explicit TraceCsv(const std::string& path);  // bop::Error naming the file if it cannot be made
    // Device and forces in scene units; forceN: the force sent to the device, N.
    void row(const LoopTick& tick, const Eigen::Vector3d& device, const ForceOutput& out,
             const Eigen::Vector3d& forceN);

private:
    std::ofstream out_;
    std::string path_;
};

struct StiffnessPoint {
    double depth = 0;  // past the surface along the poke, length
    double force = 0;  // felt against the poke direction, force (mean over the bin)
    std::size_t samples = 0;
};

// Force against depth from a poke's ticks: depth = (device - surface) . inward, force =
// -(force on the device) . inward; bins of `binWidth` from 0 to the deepest point, empty bins left out.
class StiffnessCurve {
public:
    // physical: positions in mm and forces in N (a scene with materials), written as depth_mm and
    // force_n; else scene lengths and forces, written as depth and force.
    StiffnessCurve(const Eigen::Vector3d& surface, const Eigen::Vector3d& inward, double binWidth,
                   bool physical = false);
    void add(const Eigen::Vector3d& device, const Eigen::Vector3d& force);
    std::vector<StiffnessPoint> points() const;
    void writeCsv(const std::string& path) const;

private:
    Eigen::Vector3d surface_, inward_;
    bool physical_ = false;
    double bin_;
    std::vector<double> sum_;
    std::vector<std::size_t> count_;
};

}  // namespace bop::haptic
