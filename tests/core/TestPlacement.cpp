// Placement (app/scene/Placement.hpp): every piece of a shape gets its sheet and its lattice, at the
// counts a hexagonal sheet and an fcc lattice at r0 give over the analytic area and the voxel
// volume, every particle in its own species' voxels, the same particles every time.
#include "app/scene/Placement.hpp"
#include "shape/ShapeTestUtil.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <set>

using namespace bop;
using namespace bop::core;
using namespace bop::app;

namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_CASE("placement fills both of two balls at the counts r0 spacing gives", "[core][placement]") {
    const Eigen::Vector3d a(16, 16, 16), b(42, 16, 16);  // voxel units
    const double ra = 10.3, rb = 7.6;
    const Dims d{58, 32, 32};
    const GradientMap map = test::mapFrom(
        test::depthFrom(d, {[&](const Eigen::Vector3d& x) { return (x - a).norm() < ra || (x - b).norm() < rb; }}), 2.0,
        1.5);
    const Model model = test::bagModel(map);
    const Placement placed = placeParticles(model, *model.map, {});
    const Particles& p = placed.particles;
    const double h = voxelLength(map.r0Voxels);
    REQUIRE(placed.species.size() == 2);

    // The surface: its area against the analytic spheres', its count against a hexagonal sheet's.
    const PlacedSpecies& sheet = placed.species[0];
    const double area = 4 * kPi * (ra * ra + rb * rb) * h * h;
    INFO("surface " << sheet.placed << " of " << sheet.ideal << ", area " << sheet.areaOrVolume << " against " << area
                    << "; volume " << placed.species[1].placed << " of " << placed.species[1].ideal);
    CHECK(sheet.areaOrVolume == Approx(area).epsilon(0.05));
    CHECK(double(sheet.placed) == Approx(area / (std::sqrt(3.0) / 2 * kR0 * kR0)).epsilon(0.06));
    CHECK(double(placed.species[1].placed) >= 0.8 * placed.species[1].ideal);
    CHECK(double(placed.species[1].placed) <= 1.02 * placed.species[1].ideal);

    // Each ball holds its share of both species; each particle lies in its own voxels, a surface
    // particle along the map's normal, no volume particle closer than gap_r0 to the sheet.
    std::size_t inA[3] = {0, 0, 0}, inB[3] = {0, 0, 0};
    std::set<std::uint64_t> ids;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector3d v = p.pos[i] / h;
        const std::size_t idx = d.index(int(v.x()), int(v.y()), int(v.z()));
        CHECK(int(map.occ[idx]) == int(p.species[i]));
        ((v - a).norm() < ra + 1 ? inA : inB)[p.species[i]] += 1;
        ids.insert(p.id[i]);
        if (p.species[i] == 1) CHECK(p.normal[i].dot(map.nearestSurface(idx).normal.cast<double>()) > 0.9999);
    }
    CHECK(ids.size() == p.size());
    CHECK(*ids.begin() == 1);
    CHECK(double(inA[1]) / double(inB[1]) == Approx(ra * ra / (rb * rb)).epsilon(0.15));
    CHECK(double(inA[2]) / double(inB[2]) == Approx(std::pow(ra / rb, 3)).epsilon(0.25));
    double closest = 1e9, closestSheet = 1e9;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            const double r = (p.pos[i] - p.pos[j]).norm();
            if (p.species[i] != p.species[j]) closest = std::min(closest, r);
            if (p.species[i] == 1 && p.species[j] == 1) closestSheet = std::min(closestSheet, r);
        }
    CHECK(closest >= 0.5 * kR0);
    CHECK(closestSheet >= 0.5 * kR0);  // the sheet's spacing, found for the ideal count, is not tiny

    // The same particles every time; another seed moves them.
    const Placement again = placeParticles(model, *model.map, {});
    CHECK(again.particles.pos == p.pos);
    CHECK(again.particles.id == p.id);
    PlacementParams other;
    other.seed = 7;
    CHECK(placeParticles(model, *model.map, other).particles.pos != p.pos);
}

TEST_CASE("placement needs the whole map", "[core][placement]") {
    const Dims d{20, 20, 20};
    GradientMap map = test::mapFrom(
        test::depthFrom(d, {[](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(10, 10, 10)).norm() < 6; }}));
    map.origin = Eigen::Vector3i(1, 0, 0);  // a window of a bigger map
    map.whole = Dims{21, 20, 20};
    CHECK_THROWS_AS(placeParticles(test::bagModel(map), map, {}), std::invalid_argument);
}

TEST_CASE("a mid-shell sheet is counted over the area where the map holds it", "[core][placement]") {
    const Eigen::Vector3d c(16, 16, 16);
    for (const double r : {5.2, 10.3}) {  // voxels
        const Dims d{32, 32, 32};
        const GradientMap map =
            test::mapFrom(test::depthFrom(d, {[&](const Eigen::Vector3d& x) { return (x - c).norm() < r; }}), 2.0, 1.5);
        const Model model = test::bagModel(map);
        PlacementParams mid;
        mid.sheetArea = SheetArea::MidShell;
        const Placement faces = placeParticles(model, *model.map, {}), shell = placeParticles(model, *model.map, mid);
        const double h = voxelLength(map.r0Voxels);
        const double outer = 4 * kPi * r * r * h * h, inner = 4 * kPi * (r - 0.5) * (r - 0.5) * h * h;
        INFO("radius " << r << " voxels: faces " << faces.species[0].areaOrVolume << " (sphere " << outer
                       << "), mid-shell " << shell.species[0].areaOrVolume << " (sphere at r - 1/2 " << inner
                       << "); sheet " << faces.species[0].placed << " and " << shell.species[0].placed);
        CHECK(faces.species[0].areaOrVolume == Approx(outer).epsilon(0.06));
        // Against the faces' own area (a voxel ball's faces exceed the sphere's by 1-4%): the
        // parallel surface half a voxel in, (1 - 1/(2r))^2 of it.
        CHECK(shell.species[0].areaOrVolume / faces.species[0].areaOrVolume == Approx(inner / outer).epsilon(0.04));
        CHECK(double(shell.species[0].placed) == Approx(shell.species[0].ideal).epsilon(0.01));
        // The volume is placed the same way either way, only its gap to a sparser sheet differs.
        CHECK(shell.species[1].placed >= faces.species[1].placed);
    }
}
