// Whole bags built by the construction timeline of the shipped scenes (label "physics": minutes
// of stepping, run in the Release build only): shape fidelity, elastic recovery after a poke,
// and how particle counts scale with r0 (paper Table 1).
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/scene/Fidelity.hpp"
#include "app/scene/RunStart.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <map>

using namespace bop;

namespace {

struct Built {
    app::Scene scene;
    std::unique_ptr<test::OneProcessRun> run;
    core::Simulation* sim = nullptr;  // run's
};

// Each scene is built once per test run and shared by the tests that need it.
Built& built(const std::string& name) {
    static std::map<std::string, Built> cache;
    auto it = cache.find(name);
    if (it != cache.end()) return it->second;
    Built b;
    b.scene = app::loadScene(test::sourceDir() + "/config/scenes/" + name + ".toml");
    b.run = std::make_unique<test::OneProcessRun>(b.scene);
    b.sim = &**b.run;
    b.sim->run(b.scene.run.steps);
    return cache.emplace(name, std::move(b)).first->second;
}

std::size_t count(const core::Model& m, const core::Particles& p, bool surface) {
    std::size_t n = 0;
    for (auto s : p.species) n += m.isSurface(s) == surface;
    return n;
}

}  // namespace

TEST_CASE("torus and star bags take their shape", "[physics][fidelity]") {
    for (const char* name : {"torus", "star"}) {
        Built& b = built(name);
        const app::Fidelity f = app::measureFidelity(b.sim->model(), *b.sim->mapInForce().map(), b.sim->particles());
        INFO(name << ": " << f.surface << " surface, " << f.volume << " volume particles; "
                  << 100 * f.surfaceInOwnVoxels << "% / " << 100 * f.volumeInOwnVoxels
                  << "% in their voxels; median normal angle " << f.medianNormalAngleDeg << " deg; E_kin "
                  << b.sim->stats().kinetic);
        CHECK(f.surface > 50);
        CHECK(f.volume > 30);
        CHECK(f.surfaceInOwnVoxels >= 0.98);
        CHECK(f.volumeInOwnVoxels >= 0.98);
        CHECK(f.medianNormalAngleDeg < 10.0);
        CHECK(b.sim->stats().kinetic < 0.01 * double(f.surface + f.volume));  // at rest
    }
}

TEST_CASE("a bag in a bag keeps each species in its own region", "[physics][fidelity]") {
    Built& b = built("bag-in-bag");
    const core::Model& m = b.sim->model();
    const app::Fidelity f = app::measureFidelity(m, *b.sim->mapInForce().map(), b.sim->particles());
    const double own = (f.surfaceInOwnVoxels * double(f.surface) + f.volumeInOwnVoxels * double(f.volume)) /
                       double(f.surface + f.volume);
    std::map<int, std::size_t> perSpecies;
    for (auto s : b.sim->particles().species) ++perSpecies[s];
    INFO(f.surface << " surface, " << f.volume << " volume; " << 100 * own << "% in their own species' voxels");
    CHECK(own >= 0.98);
    for (int s = 1; s <= 4; ++s) CHECK(perSpecies[s] > 20);
}

TEST_CASE("the torus recovers its shape after a 3-voxel poke", "[physics][elasticity]") {
    Built& b = built("torus");
    core::Simulation& sim = *b.sim;
    const core::Model& m = sim.model();
    for (int s = 1; s <= m.speciesCount(); ++s) sim.construction().setBirth(s, false);
    sim.run(3000);  // let the finished bag come to rest before the poke
    const double restKinetic = sim.stats().kinetic;
    const double h = core::kR0 / sim.mapInForce().map()->r0Voxels;
    std::map<std::uint64_t, Eigen::Vector3d> before;
    std::size_t top = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i) {
        before[sim.particles().id[i]] = sim.particles().pos[i];
        if (sim.particles().pos[i].z() > sim.particles().pos[top].z()) top = i;
    }
    const std::size_t n0 = sim.particles().size();
    const Eigen::Vector3d surfacePoint = sim.particles().pos[top];
    core::ProbeState& probe = sim.probe();
    probe.active = true;
    probe.params = {2.0, 3.0};  // k0: twice a particle's range, k1: three times its strength
    const Eigen::Vector3d start = surfacePoint + Eigen::Vector3d(0, 0, 2.0 * core::kR0);
    const Eigen::Vector3d deepest = surfacePoint - Eigen::Vector3d(0, 0, 3.0 * h);
    const int moveSteps = 400, holdSteps = 200;
    double maxReaction = 0;
    for (int s = 0; s <= moveSteps; ++s) {
        probe.position = start + (deepest - start) * double(s) / moveSteps;
        sim.step();
        maxReaction = std::max(maxReaction, sim.stats().forces.probeReaction.z());
    }
    for (int s = 0; s < holdSteps; ++s) sim.step();
    const core::Particles held = sim.particles();
    double maxDisplacement = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i)
        maxDisplacement =
            std::max(maxDisplacement, (sim.particles().pos[i] - before[sim.particles().id[i]]).norm() / h);
    for (int s = 0; s <= moveSteps; ++s) {
        probe.position = deepest + (start - deepest) * double(s) / moveSteps;
        sim.step();
    }
    probe.active = false;
    // RMS displacement from the pre-poke positions, voxels, over every particle or over those
    // that started within 3 r0 of the poked point (where the deformation is).
    auto rms = [&](const core::Particles& p, bool local) {
        double sum = 0;
        std::size_t n = 0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const Eigen::Vector3d& x0 = before[p.id[i]];
            if (local && (x0 - surfacePoint).norm() > 3 * core::kR0) continue;
            sum += (p.pos[i] - x0).squaredNorm();
            ++n;
        }
        return std::sqrt(sum / double(std::max<std::size_t>(n, 1))) / h;
    };
    const double heldLocal = rms(held, true), heldAll = rms(held, false);
    const GradientMap& map = *sim.mapInForce().map();  // the whole map: one process
    const app::Fidelity heldShape = app::measureFidelity(m, map, held);
    int recovered = -1;
    for (int s = 0; s <= 3000; s += 50) {
        const app::Fidelity f = app::measureFidelity(m, map, sim.particles());
        if (rms(sim.particles(), false) < 0.3 && f.surfaceInOwnVoxels >= 0.98 && f.volumeInOwnVoxels >= 0.98) {
            recovered = s;
            break;
        }
        sim.run(50);
    }
    INFO("kinetic energy before the poke "
         << restKinetic << "; largest displacement while held " << maxDisplacement
         << " voxels; largest upward reaction on the probe " << maxReaction << "; RMS displacement while held "
         << heldAll << " (near the poke " << heldLocal << "), surface particles in surface voxels while held "
         << 100 * heldShape.surfaceInOwnVoxels << "%; RMS below 0.3 voxel and shape back " << recovered
         << " steps after the " << moveSteps << "-step withdrawal (then " << rms(sim.particles(), false)
         << ", near the poke " << rms(sim.particles(), true) << ")");
    CHECK(heldLocal > 1.0);        // the poke did deform the bag where it pressed
    CHECK(maxDisplacement > 1.0);  // the poke did deform the bag
    CHECK(maxReaction > 0.0);      // and the bag pushed back
    CHECK(recovered >= 0);
    CHECK(recovered <= 2000);
    CHECK(sim.particles().size() == n0);  // no particle left or died
    const app::Fidelity f = app::measureFidelity(m, map, sim.particles());
    CHECK(f.surfaceInOwnVoxels >= 0.98);
    CHECK(f.volumeInOwnVoxels >= 0.98);
}

TEST_CASE("particle counts scale with r0 as in Table 1", "[physics][scaling]") {
    for (const char* name : {"star", "torus"}) {
        const std::string fine = std::string(name) + "-r0-1.4";
        Built& a = built(name);
        Built& b = built(fine);
        const double s2 = double(count(b.sim->model(), b.sim->particles(), true)) /
                          double(count(a.sim->model(), a.sim->particles(), true));
        const double v3 = double(count(b.sim->model(), b.sim->particles(), false)) /
                          double(count(a.sim->model(), a.sim->particles(), false));
        INFO(name << ": surface ratio " << s2 << " (expected (2/1.4)^2 = 2.04), volume ratio " << v3
                  << " (expected (2/1.4)^3 = 2.92)");
        CHECK(s2 == Approx(std::pow(2 / 1.4, 2)).epsilon(0.20));
        CHECK(v3 == Approx(std::pow(2 / 1.4, 3)).epsilon(0.20));
    }
}

TEST_CASE("construction is deterministic for a given seed, at any thread count", "[physics][construction]") {
    auto run = [](std::uint64_t seed, int threads) {
        const int before = core::threadCount();
        core::setThreadCount(threads);
        app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/star.toml");
        scene.construction.seed = seed;
        test::OneProcessRun sim(scene);
        sim->run(2000);
        core::setThreadCount(before);
        return sim->particles();
    };
    const core::Particles a = run(1, 1), b = run(1, 2), c = run(2, 1), d = run(1, 3);
    REQUIRE(a.size() > 50);
    CHECK(a.id == b.id);
    CHECK(a.pos == b.pos);
    CHECK(a.id == d.id);
    CHECK(a.pos == d.pos);
    CHECK(a.id != c.id);  // another seed makes other choices
}
