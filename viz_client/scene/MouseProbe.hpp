#pragma once
// The mouse as a probe when no haptic device is attached, GL-free: pressing puts the probe under
// the pointer and switches it on, dragging moves it in the view plane through its position (its
// depth stays), the wheel moves it along the view direction, releasing switches it off.
#include "codec/Messages.hpp"
#include "scene/Camera.hpp"

#include <cstdint>
#include <optional>

namespace bop::viz {

class MouseProbe {
public:
    // `depthStep`: how far one wheel notch moves the probe, length.
    explicit MouseProbe(double depthStep = 0.5) : depthStep_(depthStep) {}

    // The first press puts the probe on the plane through the camera's target; later ones on
    // the plane through where it last was.
    void press(double xNdc, double yNdc, const OrbitCamera& camera, double aspect);
    void drag(double xNdc, double yNdc, const OrbitCamera& camera, double aspect);
    void wheel(double notches, const OrbitCamera& camera);  // > 0: away from the eye
    void release();
    void place(const Eigen::Vector3d& position, bool active);  // a scripted probe, length

    bool active() const { return active_; }
    const Eigen::Vector3d& position() const { return position_; }  // length
    bool changed() const { return changed_; }                      // since the last message()

    // The probe to send (its sequence number is the sender's): the client's clock (ns), k0, k1.
    protocol::Probe message(std::int64_t clientNs, double k0, double k1);

private:
    double depthStep_;
    bool active_ = false, placed_ = false, changed_ = false;
    Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
};

}  // namespace bop::viz
