#include "device/ReplayDevice.hpp"

#include "bop/common/Error.hpp"
#include "recording/SessionReader.hpp"

#include <algorithm>
#include <vector>

namespace bop::haptic {
namespace {

class ReplayDevice final : public Device {
public:
    ReplayDevice(std::vector<double> t, std::vector<Eigen::Vector3d> mm, const DeviceLimits& l, std::string name)
        : t_(std::move(t)), mm_(std::move(mm)), limits_(l), name_(std::move(name)) {}
    std::string name() const override { return name_; }
    DeviceLimits limits() const override { return limits_; }
    DeviceState read(double t) override {
        DeviceState s;
        s.finished = t >= t_.back();
        const auto it = std::upper_bound(t_.begin(), t_.end(), t);
        if (it == t_.begin()) {
            s.positionMm = mm_.front();
        } else if (it == t_.end()) {
            s.positionMm = mm_.back();
        } else {
            const std::size_t k = std::size_t(it - t_.begin());
            const double u = (t - t_[k - 1]) / std::max(t_[k] - t_[k - 1], 1e-9);
            s.positionMm = (1 - u) * mm_[k - 1] + u * mm_[k];
        }
        return s;
    }
    void render(const Eigen::Vector3d&, double) override {}

private:
    std::vector<double> t_;  // s from the first probe
    std::vector<Eigen::Vector3d> mm_;
    DeviceLimits limits_;
    std::string name_;
};

}  // namespace

std::unique_ptr<Device> makeReplayDevice(const std::string& path, const Workspace& w, const DeviceLimits& limits) {
    const protocol::RecordedSession s = protocol::readSession(path);
    std::vector<double> t;
    std::vector<Eigen::Vector3d> mm;
    for (const protocol::RecordedProbe& p : s.probes) {
        const double at = 1e-9 * double(p.probe.clientTimeNs - s.probes.front().probe.clientTimeNs);
        if (!t.empty() && at <= t.back()) continue;  // time must increase
        t.push_back(at);
        mm.push_back(w.toDevice(p.probe.position));
    }
    if (t.empty()) throw Error(path, "the recording holds no probes to replay");
    return std::make_unique<ReplayDevice>(std::move(t), std::move(mm), limits, "replay:" + path);
}

}  // namespace bop::haptic
