// Keyframed gradient maps (core/Keyframes.hpp), the blood's pressure formulas, the filled volume
// of oriented surface particles, and the periodic spline of the pressure curve.
#include "app/cardiac/PeriodicSpline.hpp"
#include "core/BloodPressure.hpp"
#include "core/FilledVolume.hpp"
#include "core/Keyframes.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace bop;
using namespace bop::core;

TEST_CASE("keyframe schedule: frames switch at start + k duration, blend weight grows across each", "[keyframes]") {
    KeyframeSchedule k;
    k.frames = 8;
    k.frameDuration = 0.1;
    k.startTime = 1.0;
    k.firstFrame = 3;
    k.blend = true;
    CHECK(k.at(0.5).a == 3);  // held before the start
    CHECK(k.at(0.5).w == 0);
    const double dt = 0.02;
    for (long long step = 50; step < 50 + 5 * 24; ++step) {  // the boundary steps land on k * 5
        const KeyframeAt at = k.at(double(step) * dt);
        const long long into = step - 50;
        CHECK(at.a == int((3 + into / 5) % 8));
        CHECK(at.b == (at.a + 1) % 8);
        CHECK(at.w == Approx(double(into % 5) / 5).margin(1e-6));
    }
    k.blend = false;
    CHECK(k.at(1.13).w == 0);
    CHECK(k.at(1.13).a == 4);
    CHECK(k.period() == Approx(0.8));
    CHECK(blendFrames({10, 20, 30, 40, 50, 60, 70, 80}, {2, 3, 0.25}) == Approx(32.5));
}

TEST_CASE("map volume counts: a box's voxels split between subdomains add up to the whole", "[keyframes]") {
    GradientMap m;
    m.grid.dims = Dims{10, 8, 6};
    m.r0Voxels = 2;
    m.occ.assign(m.grid.dims.count(), 0);
    for (int z = 1; z < 5; ++z)
        for (int y = 1; y < 7; ++y)
            for (int x = 1; x < 9; ++x)
                m.occ[m.grid.dims.index(x, y, z)] = (x == 1 || x == 8 || y == 1 || y == 6 || z == 1 || z == 4) ? 1 : 2;
    const double h = kR0 / 2;
    const Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d(10, 8, 6) * h, cut(4.5 * h, 8 * h, 6 * h);
    const MapVolume whole = countMapVolume(m, lo, hi);
    CHECK(whole.bagVoxels == 8 * 6 * 4);
    CHECK(whole.volumeVoxels == 6 * 4 * 2);
    const MapVolume left = countMapVolume(m, lo, cut), right = countMapVolume(m, Eigen::Vector3d(4.5 * h, 0, 0), hi);
    CHECK(left.bagVoxels + right.bagVoxels == whole.bagVoxels);
    CHECK(left.volumeVoxels + right.volumeVoxels == whole.volumeVoxels);
    CHECK(left.bagVoxels == 3 * 6 * 4);  // centres below x = 4.5: x = 1..3 of the bag
}

TEST_CASE("filled volume: oriented points on a sphere enclose its volume, a wide hole lets the outside in",
          "[keyframes]") {
    const double h = 1.0, radius = 12.0, spacing = 1.7;
    const Dims d{40, 40, 40};
    const Eigen::Vector3d centre(20, 20, 20);
    std::vector<Eigen::Vector3d> pos, normal;
    const int n = int(4 * M_PI * radius * radius / (spacing * spacing * std::sqrt(3.0) / 2));
    for (int i = 0; i < n; ++i) {  // a Fibonacci sphere: points about `spacing` apart
        const double z = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - z * z), phi = i * M_PI * (3 - std::sqrt(5.0));
        const Eigen::Vector3d u(r * std::cos(phi), r * std::sin(phi), z);
        pos.push_back(centre + radius * u);
        normal.push_back(u);
    }
    // The sheet is the middle of a shell one voxel thick: the volume reaches h/2 beyond it.
    const double expected = 4.0 / 3 * M_PI * std::pow(radius + 0.5 * h, 3);
    const double filled = filledVoxels(d, h, pos, normal, 1.5 * spacing);
    CHECK(filled == Approx(expected).epsilon(0.03));
    std::vector<Eigen::Vector3d> holedPos, holedNormal;  // a cap of 8 voxels radius removed
    for (std::size_t i = 0; i < pos.size(); ++i)
        if ((pos[i] - (centre + radius * Eigen::Vector3d::UnitZ())).norm() > 8)
            holedPos.push_back(pos[i]), holedNormal.push_back(normal[i]);
    CHECK(filledVoxels(d, h, holedPos, holedNormal, 1.5 * spacing) <
          0.6 * expected);  // only the band inside the sheet is left
}

TEST_CASE("blood pressure: the standard virial form and the paper's eq. 15", "[keyframes]") {
    CHECK(virialPressure(30, 6, 2) == Approx(6.0));             // (30 + 6) / 6
    CHECK(paperEq15Pressure(30, 6, 3, 2) == Approx(32.0 / 6));  // (30 + 6 / 3) / 6
    CHECK(virialPressure(30, 6, 0) == 0);
}

TEST_CASE("periodic spline: through its knots, smooth across the period's ends, exact for a sine to 1e-3",
          "[keyframes]") {
    const int k = 32;
    std::vector<double> y;
    for (int i = 0; i < k; ++i) y.push_back(std::sin(2 * M_PI * i / k) + 0.3 * std::cos(4 * M_PI * i / k));
    const app::PeriodicSpline s(y);
    for (int i = 0; i < k; ++i) CHECK(s(double(i) / k) == Approx(y[std::size_t(i)]).margin(1e-12));
    for (double x = 0; x < 1; x += 0.013)
        CHECK(s(x) == Approx(std::sin(2 * M_PI * x) + 0.3 * std::cos(4 * M_PI * x)).margin(2e-3));
    CHECK(s(1.0 - 1e-9) == Approx(s(0.0)).margin(1e-6));
    CHECK(s(1.25) == Approx(s(0.25)).margin(1e-12));
}
