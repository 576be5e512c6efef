// The viewer's orbit camera (viz_client/scene/Camera.hpp): what it frames, and that pointer input
// maps onto the scene the way a user expects.
#include "scene/Camera.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace bop::viz;

namespace {

const Eigen::AlignedBox3d kBox(Eigen::Vector3d(-3, 1, 0), Eigen::Vector3d(5, 4, 20));  // length

Eigen::Vector3d corner(const Eigen::AlignedBox3d& b, int k) {
    return b.corner(Eigen::AlignedBox3d::CornerType(k));
}

}  // namespace

TEST_CASE("OrbitCamera: fit frames every corner of the box, at any aspect", "[viz]") {
    for (const double aspect : {0.5, 1.0, 16.0 / 9.0}) {
        OrbitCamera cam;
        cam.fit(kBox, aspect);
        double widest = 0;
        for (int k = 0; k < 8; ++k) {
            const Eigen::Vector3d ndc = cam.project(corner(kBox, k), aspect);
            CHECK(std::abs(ndc.x()) <= 1.0);
            CHECK(std::abs(ndc.y()) <= 1.0);
            CHECK(std::abs(ndc.z()) < 1.0);  // between the near and far planes
            widest = std::max({widest, std::abs(ndc.x()), std::abs(ndc.y())});
        }
        CHECK(widest > 0.35);  // framed, not lost in the middle (the bounding sphere fills the view)
        CHECK(cam.project(kBox.center(), aspect).head<2>().norm() < 1e-12);
    }
}

TEST_CASE("OrbitCamera: orbit keeps the target and the distance; pitch stops short of the pole", "[viz]") {
    OrbitCamera cam;
    cam.fit(kBox, 1.0);
    const double d = cam.distance();
    cam.orbit(1.3, -0.4);
    CHECK((cam.eye() - cam.target()).norm() == Approx(d).epsilon(1e-12));
    CHECK((cam.target() - kBox.center()).norm() < 1e-12);
    cam.orbit(0, 100);  // far past the pole
    CHECK(cam.forward().z() == Approx(-std::sin(OrbitCamera::kMaxPitchRad)).epsilon(1e-12));
    CHECK(cam.view().allFinite());
}

TEST_CASE("OrbitCamera: the scene follows a pan, zoom scales the distance, reset returns", "[viz]") {
    const double aspect = 1.5;
    OrbitCamera cam;
    cam.fit(kBox, aspect);
    cam.orbit(0.7, 0.2);
    const Eigen::Vector3d before = cam.target(), eye = cam.eye();
    cam.pan(0.3, -0.2, aspect);
    const Eigen::Vector3d ndc = cam.project(before, aspect);
    CHECK(ndc.x() == Approx(0.3).epsilon(1e-9));
    CHECK(ndc.y() == Approx(-0.2).epsilon(1e-9));
    CHECK(std::abs((cam.target() - before).dot(cam.forward())) < 1e-9);  // in the view plane
    const double d = cam.distance();
    cam.zoom(0.5);
    CHECK(cam.distance() == Approx(0.5 * d));
    cam.zoom(-1);  // ignored
    CHECK(cam.distance() == Approx(0.5 * d));
    cam.reset();
    CHECK((cam.target() - kBox.center()).norm() < 1e-12);
    CHECK((cam.eye() - eye).norm() > 1e-6);  // the orbit is undone too
}

TEST_CASE("OrbitCamera: the point under the pointer lies on the view plane and projects back", "[viz]") {
    const double aspect = 4.0 / 3.0;
    OrbitCamera cam;
    cam.fit(kBox, aspect);
    cam.orbit(-0.4, 0.3);
    const Eigen::Vector3d through(1, 2, 12);
    for (const auto& [x, y] : {std::pair{0.0, 0.0}, {0.5, -0.25}, {-0.9, 0.8}}) {
        const Eigen::Vector3d p = cam.onViewPlane(x, y, through, aspect);
        CHECK(std::abs((p - through).dot(cam.forward())) < 1e-9);
        const Eigen::Vector3d ndc = cam.project(p, aspect);
        CHECK(ndc.x() == Approx(x).margin(1e-9));
        CHECK(ndc.y() == Approx(y).margin(1e-9));
    }
}
