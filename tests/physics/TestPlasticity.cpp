// Lasting deformation (core/Plasticity.hpp, docs/physics.md §9.4): a slab pressed by a sphere
// probe and held past the scene's hold time keeps its dent once the probe has gone; without
// [plasticity] the slab springs back (its sheet, pushed aside by the sphere, closed by the surface
// births a release turns on); a checkpoint carries the yields.
#include "OneProcessRun.hpp"
#include "RawShapeScene.hpp"
#include "app/files/Checkpoint.hpp"
#include "app/files/ExtendedXyz.hpp"
#include "app/runs/Settling.hpp"
#include "app/scene/RunStart.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <functional>

using namespace bop;

namespace {

const Eigen::Vector3d kCentre(24, 24, 10);  // voxels of 1 mm; the slab is 40 x 40 x 12

test::Shape slab() {
    return {
        "slab",
        {48, 48, 20},
        [](const Eigen::Vector3d& x) { return (x - kCentre).cwiseAbs().maxCoeff() < 20 && std::abs(x.z() - 10) < 6; },
        0,
        [](const Eigen::Vector3d&) { return 0; }};
}

// The slab scene with a sphere probe of 3 r0 and, with `plastic`, a hold time of 10 time units.
app::Scene scene(const test::TempDir& dir, bool plastic) {
    const std::string path = test::writeScene(dir, slab());
    std::ofstream(path, std::ios::app) << "\n[probe]\nradius_mm = 16.0\n"
                                       << (plastic ? "\n[plasticity]\nhold_time = 10.0\n" : "");
    return app::loadScene(path);
}

struct Dent {
    double held = 0, after = 0;  // depth under the probe, held and after release, length
    std::size_t yields = 0;      // checks that yielded
};

// The slab's top under the probe's axis: the mean height of the five highest particles (of any
// species: the sphere pushes the sheet aside) within 1.5 r0 of the axis (voxel units in, length out).
double topUnderAxis(const core::Simulation& sim, double h) {
    const core::Particles& p = sim.particles();
    std::vector<double> z;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector3d v = p.pos[i] / h - kCentre;
        if (std::hypot(v.x(), v.y()) < 3) z.push_back(p.pos[i].z());
    }
    REQUIRE(z.size() >= 5);
    std::partial_sort(z.begin(), z.begin() + 5, z.end(), std::greater<>());
    return (z[0] + z[1] + z[2] + z[3] + z[4]) / 5;
}

// Settles the slab, lowers the probe 2 r0 into its top over 200 steps, holds 800 steps (16 time
// units), lifts it away and lets the slab relax 1,500 steps.
Dent pressAndRelease(test::OneProcessRun& run, const app::Scene& sc) {
    app::Settling settling(run.run(), sc.run);
    for (int s = 0; s < 3000 && !settling.settled(); ++s) {
        run.run().step();
        settling.afterStep(run.run());
    }
    core::Simulation& sim = *run;
    const double h = voxelLength(sim.mapInForce().map()->r0Voxels);
    const double z0 = topUnderAxis(sim, h), radius = sim.model().probeSphere->radius;
    const Eigen::Vector3d above(kCentre.x() * h, kCentre.y() * h, z0 + radius + kR0);
    core::ProbeState probe;
    probe.active = true;
    for (int s = 0; s <= 200; ++s) {
        probe.position = above - Eigen::Vector3d(0, 0, 2 * kR0 * s / 200.0);  // 1 r0 above to 1 r0 in
        sim.submit(core::ProbeCommand{probe});
        sim.step();
    }
    sim.run(800);
    Dent d;
    d.held = z0 - topUnderAxis(sim, h);
    probe.active = false;
    sim.submit(core::ProbeCommand{probe});
    sim.submit(core::BirthCommand{1, true});
    sim.run(3000);
    d.after = z0 - topUnderAxis(sim, h);
    d.yields = sim.yields().size();
    return d;
}

}  // namespace

TEST_CASE("plasticity: a dent held past the hold time stays; without it the slab springs back",
          "[physics][plasticity]") {
    test::TempDir dir("plasticity");
    const app::Scene plastic = scene(dir, true);
    REQUIRE(plastic.model->plasticity.on);
    test::OneProcessRun run(plastic, "", true);
    const Dent on = pressAndRelease(run, plastic);
    INFO("plastic: held " << on.held / kR0 << " r0, after release " << on.after / kR0 << " r0, " << on.yields
                          << " checks yielded");
    CHECK(on.held > 0.5 * kR0);  // a dent past the plasticity's least depth
    CHECK(on.yields > 0);
    // The target is within 10% of the held depth; scripts/bench/cut.sh reports the figure
    // against it. Here: the dent stays (at least 80% of it), where without plasticity none does.
    CHECK(on.after >= 0.8 * on.held);

    // The checkpoint carries the yields: a restart's map is the dented one.
    const std::string file = dir.file("dented.xyz");
    core::Simulation& sim = *run;
    app::writeCheckpoint(file, sim.gather(), sim.model(), sim.construction(), sim.stepCount(), "", sim.cuts(),
                         sim.yields());
    test::OneProcessRun again(plastic, file);
    CHECK(again->yields().size() == sim.yields().size());
    CHECK(again->mapInForce().map()->occ == sim.mapInForce().map()->occ);
    CHECK(again->mapInForce().map()->nearest == sim.mapInForce().map()->nearest);

    const app::Scene elastic = scene(dir, false);
    REQUIRE_FALSE(elastic.model->plasticity.on);
    test::OneProcessRun run2(elastic, "", true);
    const Dent off = pressAndRelease(run2, elastic);
    INFO("elastic: held " << off.held / kR0 << " r0, after release " << off.after / kR0 << " r0");
    CHECK(off.held > 0.5 * kR0);
    CHECK(off.yields == 0);
    CHECK(off.after <= 0.10 * off.held);
}
