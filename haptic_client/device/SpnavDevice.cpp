#include "device/SpnavDevice.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>

#ifdef BOP_HAVE_SPNAV
#include <spnav.h>
#endif

namespace bop::haptic {

#ifdef BOP_HAVE_SPNAV
namespace {

class SpnavDevice final : public Device {
public:
    SpnavDevice(double gain, const DeviceLimits& l) : gain_(gain), limits_(l) {
        limits_.maxForceN = 0;  // no motors
    }
    ~SpnavDevice() override { spnav_close(); }
    std::string name() const override { return "spnav"; }
    DeviceLimits limits() const override { return limits_; }
    DeviceState read(double t) override {
        spnav_event e;
        while (spnav_poll_event(&e) != 0) {
            if (e.type == SPNAV_EVENT_MOTION)
                velocity_ = Eigen::Vector3d(e.motion.x, e.motion.y, e.motion.z);
            else if (e.type == SPNAV_EVENT_BUTTON)
                buttons_ = e.button.press ? buttons_ | (1u << e.button.bnum) : buttons_ & ~(1u << e.button.bnum);
        }
        const double dt = std::clamp(t - t_, 0.0, 0.01);
        t_ = t;
        const Eigen::AlignedBox3d& box = limits_.workspaceMm;
        x_ = (x_ + dt * gain_ * velocity_).cwiseMax(box.min()).cwiseMin(box.max());
        DeviceState s;
        s.positionMm = x_;
        s.buttons = buttons_;
        return s;
    }
    void render(const Eigen::Vector3d&, double) override {}

private:
    double gain_;
    DeviceLimits limits_;
    Eigen::Vector3d x_ = Eigen::Vector3d::Zero(), velocity_ = Eigen::Vector3d::Zero();
    std::uint32_t buttons_ = 0;
    double t_ = 0;
};

}  // namespace

std::unique_ptr<Device> makeSpnavDevice(double gain, const DeviceLimits& limits) {
    if (spnav_open() == -1)
        throw Error("spnav",
                    "cannot reach spacenavd (is it installed and running, and a 3Dconnexion device plugged in?)");
    return std::make_unique<SpnavDevice>(gain, limits);
}

#else

std::unique_ptr<Device> makeSpnavDevice(double, const DeviceLimits&) {
    throw Error("spnav", "this build has no libspnav (scripts/install-deps.sh installs libspnav-dev)");
}

#endif

}  // namespace bop::haptic
