// Cutting a running bag (core::CutCommand, docs/physics.md §9): a torus cut across its tube at two
// places becomes two pieces that stay apart, each closed by its sheet on the edited map; a notch
// cut into a ball is closed by a sheet within 500 steps.
#include "OneProcessRun.hpp"
#include "RawShapeScene.hpp"
#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/Settling.hpp"
#include "app/scene/Fidelity.hpp"
#include "app/scene/RunStart.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <functional>

using namespace bop;

namespace {

const Eigen::Vector3d kTorusCentre(24, 24, 10);
constexpr double kRing = 14, kTube = 6;  // voxels

test::Shape torus() {
    return {"torus",
            {48, 48, 20},
            [](const Eigen::Vector3d& x) {
                const Eigen::Vector3d d = x - kTorusCentre;
                return std::hypot(std::hypot(d.x(), d.y()) - kRing, d.z()) < kTube;
            },
            0,
            [](const Eigen::Vector3d& x) { return x.y() < kTorusCentre.y() ? 0 : 1; }};
}

// The bag placed and settled (at most 3,000 steps).
void settle(test::OneProcessRun& run, const app::Scene& scene) {
    app::Settling settling(run.run(), scene.run);
    for (int s = 0; s < 3000 && !settling.settled(); ++s) {
        run.run().step();
        settling.afterStep(run.run());
    }
}

// A blade of radius 1 r0 drawn across the tube at the point of the ring at angle `a` (radians):
// three strokes from the hole to beyond the tube, at three heights. Simulation units.
void cutAcross(core::Simulation& sim, double a, double h) {
    const Eigen::Vector3d radial(std::cos(a), std::sin(a), 0);
    for (double dz : {-4.0, 0.0, 4.0}) {
        const Eigen::Vector3d mid = kTorusCentre + kRing * radial + Eigen::Vector3d(0, 0, dz);
        sim.submit(core::CutCommand{(mid - 9 * radial) * h, (mid + 9 * radial) * h, kR0});
    }
}

// Surface particles in surface voxels of the map in force, a fraction: of those whose position
// (voxel units) `counts`, every one without it.
double surfaceInSurfaceVoxels(const core::Simulation& sim,
                              const std::function<bool(const Eigen::Vector3d&)>& counts = {}) {
    const GradientMap& map = *sim.mapInForce().map();
    const double h = voxelLength(map.r0Voxels);
    std::size_t n = 0, in = 0;
    const core::Particles& p = sim.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (!sim.model().isSurface(p.species[i]) || (counts && !counts(p.pos[i] / h))) continue;
        ++n;
        const std::int64_t v = map.voxelHolding(p.pos[i] / h);
        in += v >= 0 && map.occ[std::size_t(v)] == p.species[i];
    }
    return n ? double(in) / double(n) : 0.0;
}
double surfaceInSurfaceVoxels(const core::Simulation& sim, int piece, const test::Shape& s) {
    return surfaceInSurfaceVoxels(sim, [&](const Eigen::Vector3d& x) { return s.piece(x) == piece; });
}

// Volume particles in a voxel of their own bag of the map in force, a fraction.
double volumeInside(const core::Simulation& sim) {
    const GradientMap& map = *sim.mapInForce().map();
    const double h = voxelLength(map.r0Voxels);
    std::size_t n = 0, in = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i) {
        const int s = sim.particles().species[i];
        if (sim.model().isSurface(s)) continue;
        ++n;
        const std::int64_t v = map.voxelHolding(sim.particles().pos[i] / h);
        in += v >= 0 && map.inBag(std::size_t(v), bagOfSpecies(s));
    }
    return n ? double(in) / double(n) : 0.0;
}

}  // namespace

TEST_CASE("a torus cut across its tube at two places: two pieces that stay apart, each closed", "[physics][cut]") {
    test::TempDir dir("cut-torus");
    const test::Shape shape = torus();
    const app::Scene scene = app::loadScene(test::writeScene(dir, shape));
    test::OneProcessRun run(scene, "", true);
    settle(run, scene);
    core::Simulation& sim = *run;
    const double h = voxelLength(sim.mapInForce().map()->r0Voxels);
    const std::size_t before = sim.particles().size();
    cutAcross(sim, 0.0, h);
    cutAcross(sim, 3.14159265358979, h);
    sim.step();  // the cuts apply at the start of the step
    REQUIRE(sim.cuts().size() == 6);
    const std::size_t removed = before - sim.particles().size();
    for (int s = 0; s < 2000; ++s) sim.step();
    const core::Particles& p = sim.particles();
    double closest = 1e300;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = 0; j < p.size(); ++j)
            if (shape.piece(p.pos[i] / h) == 0 && shape.piece(p.pos[j] / h) == 1)
                closest = std::min(closest, (p.pos[i] - p.pos[j]).norm());
    const double in0 = surfaceInSurfaceVoxels(sim, 0, shape), in1 = surfaceInSurfaceVoxels(sim, 1, shape);
    INFO(removed << " particles of " << before << " cut out; closest pair across the cuts " << closest / kR0
                 << " r0; surface particles in surface voxels " << 100 * in0 << "% and " << 100 * in1 << "%");
    CHECK(removed > 0);
    CHECK(closest > kR0);
    CHECK(in0 >= 0.95);
    CHECK(in1 >= 0.95);
    const app::Fidelity f = app::measureFidelity(sim.model(), *sim.mapInForce().map(), p);
    CHECK(f.volumeInOwnVoxels >= 0.95);
}

TEST_CASE("a checkpoint after cuts carries them: the restart's map is the cut run's, its sheet holds",
          "[physics][cut]") {
    test::TempDir dir("cut-restart");
    const test::Shape shape = torus();
    const app::Scene scene = app::loadScene(test::writeScene(dir, shape));
    test::OneProcessRun run(scene, "", true);
    settle(run, scene);
    core::Simulation& sim = *run;
    const double h = voxelLength(sim.mapInForce().map()->r0Voxels);
    cutAcross(sim, 1.0, h);
    for (int s = 0; s < 100; ++s) sim.step();
    const std::string file = dir.file("checkpoint.xyz");
    app::writeCheckpoint(file, sim.gather(), sim.model(), sim.construction(), sim.stepCount(), "", sim.cuts());
    REQUIRE(app::readExtendedXyz(file, app::speciesNames(sim.model())).info.cuts.size() == 3);

    test::OneProcessRun again(scene, file);
    const GradientMap &cut = *sim.mapInForce().map(), &restarted = *again->mapInForce().map();
    CHECK(again->cuts().size() == 3);
    CHECK(restarted.occ == cut.occ);
    CHECK(restarted.nearest == cut.nearest);
    CHECK(restarted.surface.size() == cut.surface.size());
    CHECK(again->particles().size() == sim.particles().size());
    // A blade over the whole box would take the whole bag: refused, the map and particles kept.
    const core::Box& box = again->model().box;
    const std::size_t particles = again->particles().size();
    again->submit(core::CutCommand{box.lo, box.hi, (box.hi - box.lo).norm()});
    again->step();
    CHECK(again->lastCut().refused);
    CHECK(again->cuts().size() == 3);
    CHECK(again->particles().size() == particles);
    CHECK(again->mapInForce().map()->occ == cut.occ);
    again->run(300);
    const double in = std::min(surfaceInSurfaceVoxels(*again, 0, shape), surfaceInSurfaceVoxels(*again, 1, shape));
    INFO("after the restart, surface particles in surface voxels: " << 100 * in << "% (the piece with fewer)");
    CHECK(in >= 0.95);
}

TEST_CASE("a notch cut into the bonded tissue block is closed by a sheet within 500 steps", "[physics][cut]") {
    const app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/tissue-block.toml");
    test::OneProcessRun run(scene, "", true);
    settle(run, scene);
    core::Simulation& sim = *run;
    const GradientMap before = *sim.mapInForce().map();
    const double h = voxelLength(before.r0Voxels);
    // The bag's top and its middle, voxel units.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (std::size_t v = 0; v < before.occ.size(); ++v)
        if (before.occ[v]) {
            const Eigen::Vector3d c = before.dims().coords(v).cast<double>();
            lo = lo.cwiseMin(c), hi = hi.cwiseMax(c + Eigen::Vector3d::Ones());
        }
    const Eigen::Vector3d mid = 0.5 * (lo + hi);
    // Two strokes across the top along x, the second 1.5 r0 deeper: a notch about 3.5 r0 deep.
    for (double depth : {0.0, 1.5 * before.r0Voxels}) {
        const Eigen::Vector3d a(lo.x() + 8, mid.y(), hi.z() - depth), b(hi.x() - 8, mid.y(), hi.z() - depth);
        sim.submit(core::CutCommand{a * h, b * h, kR0});
    }
    sim.step();
    const core::CutReport report = sim.lastCut();
    for (int s = 1; s < 500; ++s) sim.step();
    const GradientMap& after = *sim.mapInForce().map();
    const core::Particles& p = sim.particles();
    // Surface particles in surface voxels of the edited map; the new faces' voxels with a surface
    // particle within r0.
    std::size_t faces = 0, covered = 0;
    for (std::size_t v = 0; v < after.occ.size(); ++v) {
        if (!isSurfaceSpecies(after.occ[v]) || isSurfaceSpecies(before.occ[v])) continue;
        ++faces;
        const Eigen::Vector3d c = (after.dims().coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5)) * h;
        bool near = false;
        for (std::size_t i = 0; i < p.size() && !near; ++i)
            near = sim.model().isSurface(p.species[i]) && (p.pos[i] - c).squaredNorm() <= kR0 * kR0;
        covered += near;
    }
    const double inFraction = surfaceInSurfaceVoxels(sim), coverage = double(covered) / double(faces);
    INFO(report.removed << " particles out, " << report.converted << " made surface, " << report.bondsBroken
                        << " bonds broken; after 500 steps " << 100 * inFraction
                        << "% of surface particles in surface voxels; " << faces << " new face voxels, "
                        << 100 * coverage << "% with a surface particle within r0");
    CHECK(report.removed > 0);
    CHECK(report.bondsBroken > 0);
    CHECK(inFraction >= 0.95);
    CHECK(coverage >= 0.95);
}

TEST_CASE("a probe pushed through the whole tube: once it has gone the volume is back inside", "[physics][cut]") {
    test::TempDir dir("push-through");
    const test::Shape shape = torus();
    const std::string path = test::writeScene(dir, shape);
    std::ofstream(path, std::ios::app) << "\n[probe]\nradius_mm = 4.0\n";  // a sphere of 2 r0, the tube 6 r0 wide
    const app::Scene scene = app::loadScene(path);
    test::OneProcessRun run(scene, "", true);
    settle(run, scene);
    core::Simulation& sim = *run;
    const double h = voxelLength(sim.mapInForce().map()->r0Voxels);
    // Down through the tube at the ring's +x side, from above it to below it, over 600 steps.
    const Eigen::Vector3d top = (kTorusCentre + Eigen::Vector3d(kRing, 0, kTube + 6)) * h;
    const Eigen::Vector3d bottom = (kTorusCentre + Eigen::Vector3d(kRing, 0, -kTube - 6)) * h;
    core::ProbeState probe;
    probe.active = true;
    for (int s = 0; s <= 600; ++s) {
        probe.position = top + (bottom - top) * (s / 600.0);
        sim.submit(core::ProbeCommand{probe});
        sim.step();
    }
    probe.active = false;
    sim.submit(core::ProbeCommand{probe});
    const double justAfter = volumeInside(sim);
    sim.run(2000);
    const double later = volumeInside(sim);
    INFO("volume particles inside their bag: " << 100 * justAfter << "% as the probe leaves, " << 100 * later
                                               << "% 2,000 steps later");
    CHECK(later >= 0.99);
}

TEST_CASE("a bag squeezed to half its width: once the walls are gone the volume is back inside", "[physics][cut]") {
    test::TempDir dir("squeeze");
    const test::Shape shape = torus();
    const app::Scene scene = app::loadScene(test::writeScene(dir, shape));
    test::OneProcessRun run(scene, "", true);
    settle(run, scene);
    core::Simulation& sim = *run;
    const double h = voxelLength(sim.mapInForce().map()->r0Voxels);
    // Two walls along x, from the torus's sides (20 voxels from its axis) to half its width
    // (10 voxels) over 1,000 steps, held 200 steps: a particle past a wall is put back on it
    // with no speed into it.
    const double cx = kTorusCentre.x() * h, half = (kRing + kTube) * h;
    const auto squeeze = [&](double w) {
        core::Particles& p = sim.particles();
        for (std::size_t i = 0; i < p.size(); ++i) {
            double& x = p.pos[i].x();
            double& v = p.vel[i].x();
            if (x > cx + w) x = cx + w, v = std::min(v, 0.0);
            if (x < cx - w) x = cx - w, v = std::max(v, 0.0);
        }
    };
    for (int s = 0; s <= 1200; ++s) {
        squeeze(half * (1.0 - 0.5 * std::min(1.0, s / 1000.0)));
        sim.step();
    }
    const double squeezed = volumeInside(sim);
    double widest = 0;
    for (const Eigen::Vector3d& x : sim.particles().pos) widest = std::max(widest, std::abs(x.x() - cx));
    sim.run(2000);
    const double later = volumeInside(sim);
    INFO("volume particles inside their bag: " << 100 * squeezed << "% squeezed to half the width (the widest "
                                               << widest / half << " of the half width), " << 100 * later
                                               << "% 2,000 steps after the walls are gone");
    CHECK(widest <= 0.5 * half + 0.2 * kR0);  // squeezed: the walls' last step lets a particle move 0.2 r0
    CHECK(later >= 0.99);
}
