// Mixed precision (docs/dynamics.md "Mixed precision") on the shipped scenes: every scene of
// config/scenes, built in double for part of its run (2,000 steps at most), written as a
// checkpoint and restarted from it once in each mode, has its forces and torques in mixed within
// 1e-5 of double's (three small bags near rest miss it: kOverGate); bags built in mixed from the
// start take their shapes as faithfully as in double; and an undamped run drifts no more than
// twice as much as in double.
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/files/Checkpoint.hpp"
#include "app/scene/Fidelity.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <map>

using namespace bop;

namespace {

app::Scene inPrecision(app::Scene scene, bool mixed) {
    auto m = std::make_shared<core::Model>(*scene.model);
    m->integration.mixedPrecision = mixed;
    scene.model = std::move(m);
    return scene;
}

// |a - b| over |b|, over every particle's vector together (0 when b is all zero and a equals it).
double difference(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
    double d2 = 0, b2 = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
        d2 += (a[i] - b[i]).squaredNorm();
        b2 += b[i].squaredNorm();
    }
    return b2 > 0 ? std::sqrt(d2 / b2) : std::sqrt(d2);
}

}  // namespace

// The scenes that miss the gate of 1e-5 (issue 53), and by how much at most they may: near rest
// a particle's force and torque are small sums of larger pair terms, and float's rounding of each
// term (a few 1e-7 of it) is then a larger share of the sum. Measured on the x86-64-v4 clone:
// star 7.1e-6 force, 1.24e-5 torque; star-r0-1.4 1.05e-5 and 1.63e-5; torus-cut 1.8e-6 and
// 1.85e-5. Every other scene is held to 1e-5.
const std::map<std::string, double> kOverGate = {
    {"star.toml", 3e-5}, {"star-r0-1.4.toml", 3e-5}, {"torus-cut.toml", 3e-5}};

TEST_CASE("mixed precision: every shipped scene's forces and torques are double's to 1e-5", "[physics][mixed]") {
    std::vector<std::string> scenes;
    for (const auto& e : std::filesystem::directory_iterator(test::sourceDir() + "/config/scenes"))
        if (e.path().extension() == ".toml") scenes.push_back(e.path().string());
    std::sort(scenes.begin(), scenes.end());
    REQUIRE(scenes.size() >= 10);
    for (const std::string& path : scenes) {
        const app::Scene scene = app::loadScene(path);
        test::TempDir dir("mixed-scene");
        const std::string file = dir.file("state.xyz");
        {
            test::OneProcessRun built(inPrecision(scene, false));
            core::Simulation& sim = *built;
            // Past the start of the volume's births (step 1,500 in the timelines), at most 2e7
            // particle-steps (a scan's hundreds of thousands of particles take a hundred steps).
            for (long long s = 0;
                 s < std::min(scene.run.steps, 2000LL) && double(s) * double(sim.particles().size()) < 2e7; s += 100)
                sim.run(100);
            app::writeCheckpoint(file, sim.gather(), sim.model(), sim.construction(), sim.stepCount(), "", sim.cuts());
        }
        test::OneProcessRun dbl(inPrecision(scene, false), file), mixed(inPrecision(scene, true), file);
        dbl->refreshForces();
        mixed->refreshForces();
        const core::Particles &pd = dbl->particles(), &pm = mixed->particles();
        REQUIRE(pm.size() == pd.size());
        const double df = difference(pm.force, pd.force), dt = difference(pm.torque, pd.torque);
        const core::ForceStats &sd = dbl->stats().forces, &sm = mixed->stats().forces;
        INFO(path << ": " << pd.size() << " particles, force difference " << df << ", torque " << dt << ", pairs "
                  << sd.pairsInRange << " LJ and " << sd.orientedPairsInRange << " oriented; energy " << sd.pairEnergy
                  << " / " << sm.pairEnergy);
        const std::string name = std::filesystem::path(path).filename().string();
        const double bound = kOverGate.count(name) ? kOverGate.at(name) : 1e-5;
        CHECK(pd.size() > 0);
        CHECK(df < bound);
        CHECK(dt < bound);
        CHECK(sm.pairsInRange == sd.pairsInRange);
        CHECK(sm.orientedPairsInRange == sd.orientedPairsInRange);
        CHECK(std::abs(sm.pairEnergy - sd.pairEnergy) <= 1e-5 * std::abs(sd.pairEnergy) + 1e-9);
    }
}

TEST_CASE("mixed precision: bags built in mixed take their shapes as in double", "[physics][mixed][fidelity]") {
    for (const char* name : {"torus", "star", "bag-in-bag"}) {
        const app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/" + name + ".toml");
        app::Fidelity f[2];
        for (const bool mixed : {false, true}) {
            test::OneProcessRun run(inPrecision(scene, mixed));
            run->run(scene.run.steps);
            f[mixed] = app::measureFidelity(run->model(), *run->mapInForce().map(), run->particles());
        }
        INFO(name << ": in their own voxels, surface " << 100 * f[0].surfaceInOwnVoxels << "% double, "
                  << 100 * f[1].surfaceInOwnVoxels << "% mixed; volume " << 100 * f[0].volumeInOwnVoxels << "% / "
                  << 100 * f[1].volumeInOwnVoxels << "%; median normal angle " << f[0].medianNormalAngleDeg << " / "
                  << f[1].medianNormalAngleDeg << " deg; particles " << f[0].surface + f[0].volume << " / "
                  << f[1].surface + f[1].volume);
        CHECK(f[1].surface == f[0].surface);
        CHECK(f[1].volume == f[0].volume);
        CHECK(f[1].surfaceInOwnVoxels >= f[0].surfaceInOwnVoxels - 0.005);
        CHECK(f[1].volumeInOwnVoxels >= f[0].volumeInOwnVoxels - 0.005);
        CHECK(f[1].medianNormalAngleDeg <= f[0].medianNormalAngleDeg + 0.1);
    }
}

namespace {

// The largest |E - E0| / |E0| of an undamped run of `steps` from `start` (drags zero, no map, no
// construction: what is left is the pair energy and the kinetic energy, translation and rotation),
// in each mode, E measured every steps / 50.
struct Drift {
    double of[2] = {0, 0};  // double, mixed
};
Drift undampedDrift(const core::Model& model, const core::Params& params, const core::Particles& start,
                    long long steps) {
    Drift d;
    for (const bool mixed : {false, true}) {
        auto m = std::make_shared<core::Model>(model);
        m->integration.mixedPrecision = mixed;
        core::Params p = params;
        for (auto& drag : p.drag) drag = core::Drag{0.0, 0.0};
        core::Simulation sim(m, start, {.params = p});
        sim.refreshForces();
        const double e0 = sim.stats().total();
        for (int k = 0; k < 50; ++k) {
            sim.run(steps / 50);
            sim.refreshForces();
            d.of[mixed] = std::max(d.of[mixed], std::abs(sim.stats().total() - e0) / std::abs(e0));
        }
    }
    return d;
}

// The bulk box and the torus (built in double, then freed of its map), as the gate names them.
void checkDrift(long long steps) {
    for (const char* name : {"bulk-box", "torus"}) {
        const app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/" + name + ".toml");
        test::OneProcessRun run(inPrecision(scene, false));
        run->run(scene.run.steps);
        const Drift d = undampedDrift(run->model(), run->params(), run->particles(), steps);
        INFO(name << ", " << run->particles().size() << " particles: largest |E - E0| / |E0| over " << steps
                  << " undamped steps: double " << d.of[0] << ", mixed " << d.of[1] << " (" << d.of[1] / d.of[0]
                  << "x)");
        WARN(name << ": drift over " << steps << " steps, double " << d.of[0] << ", mixed " << d.of[1]);
        CHECK(d.of[0] < 1e-3);
        CHECK(d.of[1] <= 2 * d.of[0]);
    }
}

}  // namespace

TEST_CASE("mixed precision: an undamped bulk box and torus drift no more than twice as much as in double",
          "[physics][mixed][drift]") {
    checkDrift(5000);
}

// The gate's length, 10^5 steps (a few minutes; scripts/bench/drift.sh runs it).
TEST_CASE("mixed precision: the drift over 100,000 undamped steps", "[.][drift-long]") {
    checkDrift(100000);
}
