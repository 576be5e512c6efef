// Anti-aliased boundaries (shape/BoundarySmoothing.hpp): a smooth shape keeps its labels, a
// staircase sampled from thick slices comes closer to the surface it samples and its normals
// smooth, and any bag keeps its volume within 2%, its pieces and its holes, with the boundary
// moved by one layer of voxels at most and bags that touch still apart.
#include "shape/BoundarySmoothing.hpp"
#include "shape/Components.hpp"
#include "shape/ShapeTestUtil.hpp"
#include "shape/SimplePoint.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>

using namespace bop;
using shape::neighbourIndex;

namespace {

using Inside = std::function<bool(const Eigen::Vector3d&)>;

Mask maskOf(const Dims& d, const Inside& in) {
    return test::depthFrom(d, {in});
}

std::size_t voxels(const Mask& m) {
    return std::size_t(std::count(m.data.begin(), m.data.end(), 1));
}

// Whether voxel v of m has a face neighbour (in the grid) on the other side.
bool besideBoundary(const Mask& m, std::size_t v) {
    const Eigen::Vector3i c = m.dims.coords(v);
    for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
            Eigen::Vector3i u = c;
            u[a] += s;
            if (m.dims.contains(u.x(), u.y(), u.z()) && m(u.x(), u.y(), u.z()) != m.data[v]) return true;
        }
    return false;
}

std::size_t pieces(const Mask& m, bool object) {
    return shape::findComponents(
               m.dims, [&](std::size_t v) { return bool(m.data[v]) == object; },
               object ? shape::Neighbours::All : shape::Neighbours::Faces)
        .sizes.size();
}

// The width an image of 1 x 1 x 1.5 mm gets by default on a grid of 1 mm: its slices' thickness.
constexpr double kSliceWidth = 1.5;
// Widths a scene may give, voxels: an isotropic image's default, the slices', twice that.
const std::vector<double> kWidths = {1.0, kSliceWidth, 2.0};

// Smooths one mask at `width` and checks what every smoothing must keep.
shape::BoundarySmoothingReport smoothChecked(Mask& m, double width) {
    const Mask before = m;
    std::vector<Mask> one{m};
    const auto rep = shape::smoothBoundaries(one, {width}).front();
    m = one.front();
    INFO("removed " << rep.removed << ", added " << rep.added << ", width " << rep.widthVoxels << ", level shift "
                    << rep.levelShiftVoxels);
    CHECK(voxels(m) == rep.voxelsAfter);
    CHECK(std::abs(double(voxels(m)) / double(voxels(before)) - 1.0) <= 0.02);
    for (std::size_t v = 0; v < m.data.size(); ++v)
        if (m.data[v] != before.data[v]) REQUIRE(besideBoundary(before, v));
    CHECK(pieces(m, true) == pieces(before, true));
    CHECK(pieces(m, false) == pieces(before, false));
    return rep;
}

// Median angle between the map's normals and the true outward normal `truth`, degrees.
double medianNormalError(const Mask& m, const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& truth) {
    const GradientMap map = test::mapFrom(m, 2.0, 1.0);  // the normals with little smoothing of their own
    std::vector<double> deg;
    for (const auto& s : map.surface) {
        const Eigen::Vector3i c = map.dims().coords(s.voxel);
        const Eigen::Vector3d n = truth(c.cast<double>() + Eigen::Vector3d::Constant(0.5));
        deg.push_back(std::acos(std::clamp(double(s.normal.cast<double>().dot(n)), -1.0, 1.0)) * 180.0 / M_PI);
    }
    std::nth_element(deg.begin(), deg.begin() + std::ptrdiff_t(deg.size() / 2), deg.end());
    return deg[deg.size() / 2];
}

}  // namespace

TEST_CASE("a simple point changes side without changing the topology", "[shape][smoothing]") {
    std::array<bool, 27> n{};
    CHECK_FALSE(shape::isSimplePoint(n));  // alone: removing it deletes a piece
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) n[std::size_t(neighbourIndex(dx, dy, -1))] = true;
    CHECK(shape::isSimplePoint(n));  // on a flat face
    std::array<bool, 27> wall{};
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) wall[std::size_t(neighbourIndex(dx, dy, 0))] = true;
    CHECK_FALSE(shape::isSimplePoint(wall));  // in a wall one voxel thick: removing it opens a hole
    std::array<bool, 27> bridge{};
    bridge[std::size_t(neighbourIndex(-1, 0, 0))] = bridge[std::size_t(neighbourIndex(1, 0, 0))] = true;
    CHECK_FALSE(shape::isSimplePoint(bridge));  // joining two pieces
}

TEST_CASE("smoothing leaves a ball's labels exact", "[shape][smoothing]") {
    const Dims d{44, 44, 44};
    for (const double width : kWidths)
        for (const double r : {5.0, 6.5, 8.0, 12.0, 17.0}) {
            const Eigen::Vector3d c(22.3, 21.8, 22.1);
            Mask m = maskOf(d, [&](const Eigen::Vector3d& x) { return (x - c).norm() <= r; });
            const auto rep = smoothChecked(m, width);
            INFO("ball of radius " << r << " voxels, width " << width << ": " << rep.removed << " voxels out, "
                                   << rep.added << " in");
            CHECK(rep.removed + rep.added == 0);
        }
}

TEST_CASE("smoothing brings a staircase of thick slices to the surface it samples", "[shape][smoothing]") {
    // A ball sampled on slices 1.5 voxels thick (an image of 1 x 1 x 1.5 mm on a grid of 1 mm).
    const Dims d{48, 48, 48};
    const Eigen::Vector3d c(24.2, 23.7, 24.4);
    const double r = 15.0;
    Mask m = maskOf(d, [&](const Eigen::Vector3d& x) {
        const Eigen::Vector3d slice(x.x(), x.y(), 1.5 * std::floor(x.z() / 1.5) + 0.75);
        return (slice - c).norm() <= r;
    });
    // Voxels where the mask and the ball sampled on the grid's own voxels disagree.
    const Mask truth = maskOf(d, [&](const Eigen::Vector3d& x) { return (x - c).norm() <= r; });
    const auto offSurface = [&](const Mask& k) {
        std::size_t n = 0;
        for (std::size_t v = 0; v < k.data.size(); ++v) n += k.data[v] != truth.data[v];
        return double(n);
    };
    const auto radial = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d((x - c).normalized()); };
    const double offBefore = offSurface(m), angleBefore = medianNormalError(m, radial);
    smoothChecked(m, kSliceWidth);
    const double offAfter = offSurface(m), angleAfter = medianNormalError(m, radial);
    const double angleIdeal = medianNormalError(truth, radial);
    INFO(offBefore << " -> " << offAfter << " voxels unlike the ball sampled on the grid; median normal error "
                   << angleBefore << " -> " << angleAfter << " deg (" << angleIdeal
                   << " on the ball sampled on the grid)");
    CHECK(offAfter < 0.8 * offBefore);
    CHECK(angleAfter - angleIdeal < 2.0 / 3.0 * (angleBefore - angleIdeal));  // a third of the way at least
}

TEST_CASE("smoothing keeps thin parts, noisy shapes' volumes and touching bags apart", "[shape][smoothing]") {
    const Dims d{40, 40, 40};
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Eigen::Vector3i> bumps;
    for (int i = 0; i < 200; ++i) bumps.emplace_back(int(40 * u(rng)), int(40 * u(rng)), int(40 * u(rng)));
    const Eigen::Vector3d c(20.1, 19.6, 20.3);
    const std::vector<std::pair<std::string, Inside>> shapes = {
        {"tube of radius 2", [](const Eigen::Vector3d& x) { return std::hypot(x.x() - 20.3, x.y() - 19.8) <= 2.0; }},
        {"plate 1 voxel thick", [](const Eigen::Vector3d& x) { return std::abs(x.z() - 0.3 * x.x() - 12.0) <= 0.5; }},
        {"plate 2 voxels thick", [](const Eigen::Vector3d& x) { return std::abs(x.z() - 0.3 * x.x() - 12.0) <= 1.0; }},
        {"noisy ball",
         [&](const Eigen::Vector3d& x) {
             const Eigen::Vector3i v = x.array().floor().cast<int>();
             const bool bump = std::find(bumps.begin(), bumps.end(), v) != bumps.end();
             return ((x - c).norm() <= 12.0) != (bump && std::abs((x - c).norm() - 12.0) < 1.5);
         }},
    };
    for (const double width : kWidths)
        for (const auto& [name, in] : shapes) {
            Mask m = maskOf(d, in);
            INFO(name << ", width " << width);
            const auto rep = smoothChecked(m, width);
            if (name == "noisy ball") CHECK(rep.removed + rep.added > 0);
        }

    // Two bags that share a tilted face: they trade voxels and neither overlaps the other.
    const auto below = [](const Eigen::Vector3d& x) { return x.z() < 0.37 * x.x() + 0.21 * x.y() + 8.0; };
    std::vector<Mask> two{maskOf(d, [&](const Eigen::Vector3d& x) { return (x - c).norm() <= 15 && below(x); }),
                          maskOf(d, [&](const Eigen::Vector3d& x) { return (x - c).norm() <= 15 && !below(x); })};
    const std::size_t together = voxels(two[0]) + voxels(two[1]);
    shape::smoothBoundaries(two, {kSliceWidth, kSliceWidth});
    for (std::size_t v = 0; v < two[0].data.size(); ++v) REQUIRE(!(two[0].data[v] && two[1].data[v]));
    CHECK(double(voxels(two[0]) + voxels(two[1])) >= 0.995 * double(together));
}
