// Bags of shapes with thin parts and several pieces. Placed on their maps and relaxed until
// settled (app/scene/Placement.hpp, scene without a construction timeline): a plate a tenth as thick
// as it is wide and a label of two separate balls, each within the real-shapes targets: >= 95% of
// surface particles in surface voxels, >= 98% of volume particles in volume voxels, median normal
// angle <= 10 deg, counts within 10% of a hexagonal sheet at r0 over the analytic area and of an
// fcc lattice at r0 over the volume voxels, and settled (kinetic energy per particle <= 1e-4 at
// every check over 50 steps, app/runs/SettleWatch.hpp; by the minimiser, then the dynamics,
// app/runs/Settling.hpp). Built by
// birth and death from the torus scene's timeline (app/scene/PieceSeeds.hpp): each ball grows
// its sheet and its volume from seeds of its own.
#include "OneProcessRun.hpp"
#include "RawShapeScene.hpp"
#include "TestUtil.hpp"
#include "app/runs/SettleWatch.hpp"
#include "app/runs/Settling.hpp"
#include "app/scene/Fidelity.hpp"
#include "app/scene/RunStart.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace bop;

namespace {

constexpr double kPi = 3.14159265358979323846;
using test::Shape;
using test::writeScene;

const Eigen::Vector3d ca(18, 17, 17), cb(48, 17, 17);  // the two balls' centres, voxel units

Shape twoBalls() {
    return {"two-balls",
            {66, 34, 34},
            [](const Eigen::Vector3d& x) { return (x - ca).norm() < 12 || (x - cb).norm() < 9; },
            4 * kPi * (12 * 12 + 9 * 9),
            [](const Eigen::Vector3d& x) { return (x - ca).norm() < 14 ? 0 : 1; }};
}

// Steps the run until `settling` finds it settled or the scene's step limit; the steps taken.
long long settleRun(test::OneProcessRun& run, const app::Scene& scene, app::Settling& settling) {
    long long steps = 0;
    while (!settling.settled() && steps < scene.run.steps) {
        run.run().step();
        ++steps;
        settling.afterStep(run.run());
    }
    return steps;
}

// A closed membrane one voxel thick (a hollow organ's wall): the voxels within half a voxel of a
// sphere of radius 12 voxels.
const Eigen::Vector3d cm(16.3, 15.8, 16.1);
constexpr double kMembraneRadius = 12.0;

bool onMembrane(const Eigen::Vector3d& x) {
    return std::abs((x - cm).norm() - kMembraneRadius) <= 0.5;
}

}  // namespace

TEST_CASE("a bag is settled once its kinetic energy stays low over the calm span, not at a passing dip",
          "[physics][placement]") {
    // Checks 10 steps apart over 50 steps: six calm checks in a row.
    app::SettleWatch watch(1e-4, 10, 50);
    CHECK(watch.checksNeeded() == 6);
    for (int k = 0; k < 5; ++k) CHECK_FALSE(watch.observe(5e-5));
    CHECK_FALSE(watch.observe(2e-4));  // the dip ends: the count starts again
    for (int k = 0; k < 5; ++k) CHECK_FALSE(watch.observe(1e-4));
    CHECK(watch.observe(1e-4));  // at the threshold counts as calm; six in a row span 50 steps
    CHECK(watch.settled());
    // Checks as far apart as the span: two calm checks, the rule of checks every 50 steps.
    app::SettleWatch sparse(1e-4, 50, 50);
    CHECK(sparse.checksNeeded() == 2);
    CHECK_FALSE(sparse.observe(1e-5));
    CHECK(sparse.observe(1e-5));
    // No span: the first calm check; a span not a multiple of the period rounds up.
    CHECK(app::SettleWatch(1e-4, 10, 0).observe(0.0));
    CHECK(app::SettleWatch(1e-4, 20, 50).checksNeeded() == 4);
    CHECK(watch.due(30));
    CHECK_FALSE(watch.due(35));
}

TEST_CASE("a thin plate and two balls placed and settled within the targets", "[physics][placement]") {
    const std::vector<Shape> shapes = {
        {"plate",
         {52, 52, 20},
         [](const Eigen::Vector3d& x) {
             return x.x() > 6 && x.x() < 46 && x.y() > 6 && x.y() < 46 && x.z() > 6 && x.z() < 14;
         },
         2 * 40 * 40 + 4 * 40 * 8,
         [](const Eigen::Vector3d&) { return 0; }},
        twoBalls(),
    };
    for (const Shape& s : shapes) {
        test::TempDir dir("placed-bags");
        app::Scene scene = app::loadScene(writeScene(dir, s));
        REQUIRE(scene.placement);
        REQUIRE(scene.run.untilSettled);
        test::OneProcessRun run(scene, "", true);      // at the settle time step, as bop-server's batch run settles it
        app::Settling settling(run.run(), scene.run);  // the minimiser, then the dynamics, as bop-server settles it
        REQUIRE(run.run().minimising());
        const long long steps = settleRun(run, scene, settling);
        const core::Particles& p = run->particles();
        const GradientMap map = run.wholeMap();
        const app::Fidelity f = app::measureFidelity(*scene.model, map, p);
        const double h = voxelLength(map.r0Voxels);
        const double surfaceIdeal = s.area / (std::sqrt(3.0) / 2 * map.r0Voxels * map.r0Voxels);
        const double volumeIdeal =
            double(std::count(map.occ.begin(), map.occ.end(), 2)) / std::pow(map.r0Voxels, 3) * std::sqrt(2.0);
        std::size_t perPiece[2][3] = {};
        for (std::size_t i = 0; i < p.size(); ++i) perPiece[s.piece(p.pos[i] / h)][p.species[i]] += 1;
        INFO(s.name << ": settled after " << steps << " steps; " << f.surface << " surface (ideal " << surfaceIdeal
                    << "), " << f.volume << " volume (ideal " << volumeIdeal << "); " << 100 * f.surfaceInOwnVoxels
                    << "% / " << 100 * f.volumeInOwnVoxels << "% in their voxels, median normal angle "
                    << f.medianNormalAngleDeg << " deg");
        CHECK(settling.settled());
        CHECK(settling.minimiserSteps() > 0);
        CHECK_FALSE(run.run().minimising());
        CHECK(f.surfaceInOwnVoxels >= 0.95);
        CHECK(f.volumeInOwnVoxels >= 0.98);
        CHECK(f.medianNormalAngleDeg <= 10.0);
        CHECK(double(f.surface) == Approx(surfaceIdeal).epsilon(0.10));
        CHECK(double(f.volume) == Approx(volumeIdeal).epsilon(0.10));
        if (std::string(s.name) == "two-balls")
            for (int piece = 0; piece < 2; ++piece) {
                CHECK(perPiece[piece][1] > 100);  // every piece has its sheet and its volume
                CHECK(perPiece[piece][2] > 100);
            }
    }
}

TEST_CASE("two balls built by birth, each from seeds of its own", "[physics][construction]") {
    const Shape s = twoBalls();
    test::TempDir dir("birth-bags");
    app::Scene scene = app::loadScene(writeScene(dir, s, true));
    REQUIRE(!scene.placement);
    test::OneProcessRun run(scene);  // its start seeds every piece (app::startRun)
    run.run().run(4000);
    const core::Particles& p = run->particles();
    const double h = voxelLength(run.wholeMap().r0Voxels);
    std::size_t perPiece[2][3] = {};
    for (std::size_t i = 0; i < p.size(); ++i) perPiece[s.piece(p.pos[i] / h)][p.species[i]] += 1;
    INFO("ball a: " << perPiece[0][1] << " surface, " << perPiece[0][2] << " volume; ball b: " << perPiece[1][1]
                    << " surface, " << perPiece[1][2] << " volume");
    // A sheet of the smaller ball (radius 9 voxels = 4.5 r0) holds about 4 pi 4.5^2 / (sqrt(3)/2)
    // = 294 particles at r0 spacing, its volume about 4/3 pi 4.5^3 sqrt(2) = 540 less the sheet's
    // layer: well over 100 of each in both balls when each grew from a seed of its own.
    for (int piece = 0; piece < 2; ++piece) {
        CHECK(perPiece[piece][1] > 100);
        CHECK(perPiece[piece][2] > 100);
    }
}

TEST_CASE("a membrane one voxel thick holds a single sheet", "[physics][placement]") {
    // Faces on both sides of a part thinner than 2 r0 count half (app/scene/Placement.hpp): one sheet
    // of about 4 pi R^2 / (sqrt(3)/2 r0^2) particles, where two sheets, one per side, would not fit.
    const Shape s{
        "membrane", {33, 33, 33}, onMembrane, 4 * kPi * kMembraneRadius * kMembraneRadius, [](const Eigen::Vector3d&) {
            return 0;
        }};
    test::TempDir dir("membrane");
    app::Scene scene = app::loadScene(writeScene(dir, s));
    test::OneProcessRun run(scene, "", true);
    app::Settling settling(run.run(), scene.run);
    const long long steps = settleRun(run, scene, settling);
    const core::Particles& p = run->particles();
    const GradientMap map = run.wholeMap();
    const double h = voxelLength(map.r0Voxels);
    const double sheet = s.area / (std::sqrt(3.0) / 2 * map.r0Voxels * map.r0Voxels);
    std::size_t surface = 0, inside = 0;
    std::vector<double> angles;  // between each particle's normal and the sphere's, degrees
    for (std::size_t i = 0; i < p.size(); ++i) {
        surface += scene.model->isSurface(p.species[i]);
        const std::int64_t v = map.voxelHolding(p.pos[i] / h);
        inside += v >= 0 && map.occ[std::size_t(v)] != 0;
        const Eigen::Vector3d radial = (p.pos[i] / h - cm).normalized();
        angles.push_back(std::acos(std::clamp(std::abs(p.normal[i].dot(radial)), 0.0, 1.0)) * 180 / kPi);
    }
    std::nth_element(angles.begin(), angles.begin() + std::ptrdiff_t(angles.size() / 2), angles.end());
    INFO("settled after " << steps << " steps; " << p.size() << " particles, " << surface << " surface (one sheet: "
                          << sheet << "); " << inside << " inside the membrane; median angle of the normals to the "
                          << "sphere's axis " << angles[angles.size() / 2] << " deg");
    CHECK(settling.settled());
    CHECK(surface == p.size());  // no volume in a membrane
    CHECK(double(surface) == Approx(sheet).epsilon(0.1));
    CHECK(double(inside) >= 0.99 * double(p.size()));
    CHECK(angles[angles.size() / 2] < 10.0);
}
