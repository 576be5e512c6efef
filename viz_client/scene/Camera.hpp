#pragma once
// The viewer's orbit camera, GL-free: it looks at a target from a distance along a direction
// given by yaw and pitch (z is up), and gives OpenGL's view and projection matrices. Mouse input
// maps onto orbit (drag), pan (drag with a modifier: the scene follows the pointer), zoom (wheel);
// fit() frames a box, reset() returns to the last fit. onViewPlane() turns a pointer position
// into a point in the scene, for seeding particles and for the mouse probe.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bop::viz {

class OrbitCamera {
public:
    static constexpr double kDefaultFovYRad = 0.7853981633974483;  // 45 degrees, vertical
    static constexpr double kMaxPitchRad = 1.5533430342749532;     // 89 degrees: up never flips

    OrbitCamera();

    // Frames the box: its bounding sphere fits the view at this aspect (width / height), seen
    // from the current direction. Remembered for reset().
    void fit(const Eigen::AlignedBox3d& box, double aspect);
    void reset();
    void orbit(double dYawRad, double dPitchRad);  // about the target; pitch clamped to +-89 degrees
    // Moves the target in the view plane so that what was under the pointer at NDC (0, 0) comes
    // under (dx, dy): the scene follows a drag of (dx, dy) in NDC units (-1..1 across the view).
    void pan(double dxNdc, double dyNdc, double aspect);
    void zoom(double factor);  // distance to the target times factor (> 0); < 1 comes closer

    Eigen::Vector3d target() const { return target_; }
    Eigen::Vector3d eye() const;
    Eigen::Vector3d forward() const;  // unit, from the eye towards the target
    double distance() const { return distance_; }

    Eigen::Matrix4d view() const;                     // world -> eye coordinates
    Eigen::Matrix4d projection(double aspect) const;  // eye -> clip coordinates, near/far around the scene
    // World point to normalised device coordinates (x, y in -1..1 across the view, z in -1..1
    // between the near and far planes).
    Eigen::Vector3d project(const Eigen::Vector3d& p, double aspect) const;
    // The point under the pointer at NDC (x, y) on the plane through `through` facing the camera.
    Eigen::Vector3d onViewPlane(double xNdc, double yNdc, const Eigen::Vector3d& through, double aspect) const;

private:
    struct Pose {
        Eigen::Vector3d target = Eigen::Vector3d::Zero();
        double distance = 10;           // length
        double yaw = 0.6, pitch = 0.4;  // rad
    };
    Eigen::Vector3d right() const;  // unit, to the right of the view
    Eigen::Vector3d up() const;     // unit, up in the view

    Eigen::Vector3d target_;
    double distance_, yaw_, pitch_;
    double sceneRadius_ = 1;  // length, for the near and far planes
    double fovY_ = kDefaultFovYRad;
    Pose home_;
};

}  // namespace bop::viz
