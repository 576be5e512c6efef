#include "app/Traces.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bop::haptic {

TraceCsv::TraceCsv(const std::string& path) : out_(path), path_(path) {
    if (!out_) throw Error(path, "cannot write the haptic trace");
    out_ << "t_s,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,server_fx,server_fy,server_fz,field_fx,field_fy,"
            "field_fz,force_fx,force_fy,force_fz,force_n,gain,feedback_age_ms,late_us\n";
}

void TraceCsv::row(const LoopTick& t, const Eigen::Vector3d& d, const ForceOutput& o, const Eigen::Vector3d& n) {
    char line[512];
    const double age = std::min(o.feedbackAgeS, 1e6) * 1000;
    std::snprintf(
        line, sizeof line,
        "%.6f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g,%.4f,%.3f,%.1f\n", t.tS,
        d.x(), d.y(), d.z(), o.proxy.x(), o.proxy.y(), o.proxy.z(), o.server.x(), o.server.y(), o.server.z(),
        o.field.x(), o.field.y(), o.field.z(), o.force.x(), o.force.y(), o.force.z(), n.norm(), o.gain, age, t.lateUs);
    out_ << line;
    if (t.index % 100 == 0) out_.flush();  // whoever follows the file sees it grow
}

StiffnessCurve::StiffnessCurve(const Eigen::Vector3d& surface, const Eigen::Vector3d& inward, double binWidth,
                               bool physical)
    : surface_(surface), inward_(inward.normalized()), physical_(physical), bin_(binWidth) {}

void StiffnessCurve::add(const Eigen::Vector3d& device, const Eigen::Vector3d& force) {
    const double depth = (device - surface_).dot(inward_);
    if (depth < 0) return;
    const auto b = std::size_t(depth / bin_);
    if (b >= sum_.size()) sum_.resize(b + 1, 0.0), count_.resize(b + 1, 0);
    sum_[b] += -force.dot(inward_);
    ++count_[b];
}

std::vector<StiffnessPoint> StiffnessCurve::points() const {
    std::vector<StiffnessPoint> p;
    for (std::size_t b = 0; b < sum_.size(); ++b)
        if (count_[b] > 0) p.push_back({(double(b) + 0.5) * bin_, sum_[b] / double(count_[b]), count_[b]});
    return p;
}

void StiffnessCurve::writeCsv(const std::string& path) const {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the stiffness curve");
    out << (physical_ ? "depth_mm,force_n,samples\n" : "depth,force,samples\n");
    for (const StiffnessPoint& p : points()) out << p.depth << ',' << p.force << ',' << p.samples << '\n';
}

}  // namespace bop::haptic
