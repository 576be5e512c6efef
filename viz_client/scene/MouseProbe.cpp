#include "scene/MouseProbe.hpp"

namespace bop::viz {

void MouseProbe::press(double x, double y, const OrbitCamera& camera, double aspect) {
    position_ = camera.onViewPlane(x, y, placed_ ? position_ : camera.target(), aspect);
    placed_ = active_ = changed_ = true;
}

void MouseProbe::drag(double x, double y, const OrbitCamera& camera, double aspect) {
    if (!active_) return;
    position_ = camera.onViewPlane(x, y, position_, aspect);
    changed_ = true;
}

void MouseProbe::wheel(double notches, const OrbitCamera& camera) {
    if (!placed_) return;
    position_ += notches * depthStep_ * camera.forward();
    changed_ = true;
}

void MouseProbe::release() {
    changed_ = changed_ || active_;
    active_ = false;
}

void MouseProbe::place(const Eigen::Vector3d& position, bool active) {
    position_ = position;
    placed_ = changed_ = true;
    active_ = active;
}

protocol::Probe MouseProbe::message(std::int64_t clientNs, double k0, double k1) {
    changed_ = false;
    protocol::Probe p;
    p.clientTimeNs = clientNs;
    p.position = position_;
    p.active = active_;
    p.k0 = k0;
    p.k1 = k1;
    return p;
}

}  // namespace bop::viz
