#include "scene/Camera.hpp"

#include <algorithm>
#include <cmath>

namespace bop::viz {

OrbitCamera::OrbitCamera() {
    target_ = home_.target;
    distance_ = home_.distance;
    yaw_ = home_.yaw;
    pitch_ = home_.pitch;
}

void OrbitCamera::fit(const Eigen::AlignedBox3d& box, double aspect) {
    sceneRadius_ = std::max(0.5 * box.diagonal().norm(), 1e-9);
    const double halfY = 0.5 * fovY_, halfX = std::atan(aspect * std::tan(halfY));
    target_ = box.center();
    distance_ = sceneRadius_ / std::sin(std::min(halfX, halfY));  // the sphere touches the narrower sides
    home_ = {target_, distance_, yaw_, pitch_};
}

void OrbitCamera::reset() {
    target_ = home_.target;
    distance_ = home_.distance;
    yaw_ = home_.yaw;
    pitch_ = home_.pitch;
}

void OrbitCamera::orbit(double dYaw, double dPitch) {
    yaw_ += dYaw;
    pitch_ = std::clamp(pitch_ + dPitch, -kMaxPitchRad, kMaxPitchRad);
}

void OrbitCamera::pan(double dx, double dy, double aspect) {
    const double halfHeight = distance_ * std::tan(0.5 * fovY_);  // of the view plane through the target
    target_ -= dx * halfHeight * aspect * right() + dy * halfHeight * up();
}

void OrbitCamera::zoom(double factor) {
    if (factor > 0 && std::isfinite(factor)) distance_ = std::max(distance_ * factor, 1e-6 * sceneRadius_);
}

Eigen::Vector3d OrbitCamera::forward() const {
    // The eye sits at target + distance * (cos p cos y, cos p sin y, sin p) and looks back.
    return -Eigen::Vector3d(std::cos(pitch_) * std::cos(yaw_), std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_));
}

Eigen::Vector3d OrbitCamera::eye() const {
    return target_ - distance_ * forward();
}
Eigen::Vector3d OrbitCamera::right() const {
    return forward().cross(Eigen::Vector3d::UnitZ()).normalized();
}
Eigen::Vector3d OrbitCamera::up() const {
    return right().cross(forward());
}

Eigen::Matrix4d OrbitCamera::view() const {
    const Eigen::Vector3d f = forward(), r = right(), u = up(), e = eye();
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    m.block<1, 3>(0, 0) = r.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -r.dot(e);
    m(1, 3) = -u.dot(e);
    m(2, 3) = f.dot(e);
    return m;
}

Eigen::Matrix4d OrbitCamera::projection(double aspect) const {
    // Near and far hold the scene's bounding sphere (and a margin) wherever the target moved.
    const double margin = 2 * sceneRadius_;
    const double zNear = std::max(distance_ - margin, 1e-3 * distance_), zFar = distance_ + margin;
    const double t = 1.0 / std::tan(0.5 * fovY_);
    Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
    p(0, 0) = t / aspect;
    p(1, 1) = t;
    p(2, 2) = -(zFar + zNear) / (zFar - zNear);
    p(2, 3) = -2 * zFar * zNear / (zFar - zNear);
    p(3, 2) = -1;
    return p;
}

Eigen::Vector3d OrbitCamera::project(const Eigen::Vector3d& x, double aspect) const {
    const Eigen::Vector4d c = projection(aspect) * view() * x.homogeneous();
    return c.head<3>() / c.w();
}

Eigen::Vector3d OrbitCamera::onViewPlane(double xNdc, double yNdc, const Eigen::Vector3d& through,
                                         double aspect) const {
    const double tanHalf = std::tan(0.5 * fovY_);
    const Eigen::Vector3d f = forward();
    const Eigen::Vector3d ray = f + xNdc * tanHalf * aspect * right() + yNdc * tanHalf * up();  // f . ray = 1
    const double depth = f.dot(through - eye());  // the plane's distance along the view direction
    return eye() + depth * ray;
}

}  // namespace bop::viz
