// A state the run may go on from (core/SoundState.hpp): a step that ends with a non-finite value
// or a runaway particle throws UnsoundState naming the particle, whatever the blow-up; the probe's
// force stays bounded when it sits on a particle; a seed on a particle is not placed; positions
// wrap into a periodic box.
#include "core/ConstructionSteps.hpp"
#include "core/Potentials.hpp"
#include "core/Simulation.hpp"
#include "core/SoundState.hpp"

#include <catch2/catch.hpp>

#include <limits>

using namespace bop;
using namespace bop::core;

namespace {

// Three volume particles at the LJ spacing in a box of 10 r0, damped.
std::shared_ptr<Model> smallModel(bool periodic = false) {
    auto m = std::make_shared<Model>();
    m->species.assign(2, Species{});
    m->species[1].kind = ParticleKind::Volume;
    m->box.hi = Eigen::Vector3d::Constant(10 * kR0);
    m->box.periodic = {periodic, periodic, periodic};
    return m;
}

Particles three() {
    Particles p;
    const Eigen::Vector3d c = Eigen::Vector3d::Constant(5 * kR0);
    for (int k = 0; k < 3; ++k) p.add(c + Eigen::Vector3d(k * kR0, 0, 0), 1, std::uint64_t(k + 1));
    return p;
}

Simulation simulation(const std::shared_ptr<Model>& m, Particles p) {
    Simulation s(m, std::move(p), {.construction = Construction({}, {}, m->speciesCount())});
    s.refreshForces();
    return s;
}

}  // namespace

TEST_CASE("a step that ends with a non-finite value throws UnsoundState naming the particle and what",
          "[core][sound]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    struct Spoil {
        const char* what;  // what the state after the step says
        bool limit;        // with the step limit (Integration::maxStepR0)
        void (*apply)(Particles&, double);
    };
    const Spoil spoils[] = {
        {"position not finite", true, [](Particles& p, double x) { p.vel[1].y() = x; }},  // the drift spreads it
        {"position not finite", true, [](Particles& p, double x) { p.pos[1].z() = x; }},
        {"more than 1e6 length units beyond the box", true, [](Particles& p, double) { p.pos[1].x() = -2e6; }},
        {"more than 1e6 length units beyond the box", false, [](Particles& p, double) { p.vel[1].x() = 1e300; }},
        {"position not finite", false, [](Particles& p, double) { p.vel[1].x() = 1e308 * 10; }},
    };
    for (const Spoil& s : spoils) {
        const auto m = smallModel();
        if (!s.limit) m->integration.maxStepR0 = 0;
        Simulation sim = simulation(m, three());
        sim.run(5);
        REQUIRE(sound(*m, sim.particles(), Eigen::Vector3d::Zero()));
        s.apply(sim.particles(), nan);
        INFO(s.what);
        try {
            sim.step();
            FAIL("no UnsoundState");
        } catch (const UnsoundState& e) {
            CHECK(e.step() == 6);
            CHECK_THAT(e.what(), Catch::Contains("particle 2 (species 1): ") && Catch::Contains(s.what));
        }
        CHECK_FALSE(sound(*m, sim.particles(), Eigen::Vector3d::Zero()));
    }
    // The probe's reaction counts too.
    const auto m = smallModel();
    const Simulation ok = simulation(m, three());
    CHECK(unsoundness(*m, ok.particles(), Eigen::Vector3d(0, nan, 0)) == "the probe's reaction force not finite");
    CHECK(unsoundness(*m, ok.particles(), Eigen::Vector3d::Zero()).empty());
    // A start (a restart file's state) checked before any drift: too fast to step.
    Particles fast = three();
    fast.vel[2].z() = -2e6 / m->integration.dt;
    CHECK(unsoundness(*m, fast, Eigen::Vector3d::Zero()) ==
          "particle 3 (species 1): faster than 1e6 length units a step");
}

TEST_CASE("the step limit holds a particle shot at 1e300 to 0.2 r0 a step, and changes nothing below it",
          "[core][sound]") {
    const auto m = smallModel();
    Simulation sim = simulation(m, three());
    sim.particles().vel[1].x() = 1e300;
    const Eigen::Vector3d before = sim.particles().pos[1];
    sim.step();
    CHECK(sound(*m, sim.particles(), Eigen::Vector3d::Zero()));
    CHECK((sim.particles().pos[1] - before).norm() <= m->integration.maxStepR0 * kR0 * (1 + 1e-12));
    // A run that never meets the limit is the same bit for bit with and without it.
    const auto free = smallModel();
    free->integration.maxStepR0 = 0;
    free->integration.maxTurn = 0;
    Simulation a = simulation(m, three()), b = simulation(free, three());
    a.particles().vel[0] = b.particles().vel[0] = Eigen::Vector3d(0.3, -0.2, 0.1);
    a.run(50);
    b.run(50);
    for (std::size_t i = 0; i < 3; ++i) CHECK(a.particles().pos[i] == b.particles().pos[i]);
}

TEST_CASE("two particles on one point: the forces blow up and the step says so", "[core][sound]") {
    const auto m = smallModel();
    Particles p = three();
    p.pos[2] = p.pos[1];  // r = 0: f(r) is infinite
    Simulation sim(m, std::move(p), {.construction = Construction({}, {}, 1)});
    CHECK_THROWS_AS(sim.step(), UnsoundState);
}

TEST_CASE("the probe's force is that of its core's edge inside it, -dE/dr holds, and it is 0 on the particle",
          "[core][potentials][probe]") {
    for (const ProbeParams pp : {ProbeParams{1.0, 1.0}, ProbeParams{0.3, 50.0}, ProbeParams{4.0, 0.2}}) {
        const ProbeForm probe(LjForm(), pp);
        const double core = kProbeCoreR0 * pp.k0 * kR0;
        double fEdge = 0, eEdge = 0;
        REQUIRE(probe.eval(core * core * (1 + 1e-12), fEdge, eEdge));
        const double edgeForce = fEdge * core;
        CHECK(edgeForce == Approx(pp.k1 * LjForm().force(kProbeCoreR0 * kR0)).epsilon(1e-9));
        for (const double r : {0.9 * core, 0.5 * core, 1e-3 * core, 1e-150}) {
            double f = 0, e = 0;
            REQUIRE(probe.eval(r * r, f, e));
            CHECK(f * r == Approx(edgeForce).epsilon(1e-9));  // the force's size
            CHECK(std::isfinite(e));
            if (r < 1e-100) continue;
            const double h = 1e-6 * core;  // -dE/dr by central differences
            double fp = 0, ep = 0, fm = 0, em = 0;
            probe.eval((r + h) * (r + h), fp, ep);
            probe.eval((r - h) * (r - h), fm, em);
            CHECK(-(ep - em) / (2 * h) == Approx(edgeForce).epsilon(1e-6));
        }
        double f = 1, e = 0;
        REQUIRE(probe.eval(0.0, f, e));
        CHECK(f == 0.0);
        CHECK(e == Approx(eEdge + edgeForce * core).epsilon(1e-9));
    }
}

TEST_CASE("a probe dropped onto a particle pushes it with a bounded force, and the state stays sound",
          "[core][sound][probe]") {
    const auto m = smallModel();
    Simulation sim = simulation(m, three());
    sim.probe().active = true;
    sim.probe().position = sim.particles().pos[1];  // exactly on particle 2
    sim.probe().params = {1.0, 50.0};
    sim.refreshForces();
    CHECK(sim.particles().force[1].allFinite());
    sim.probe().position += Eigen::Vector3d(1e-9, 0, 0);
    sim.run(50);
    CHECK(sound(*m, sim.particles(), sim.stats().forces.probeReaction));
    CHECK(sim.stats().forces.probeReaction.norm() <= 3 * 50 * LjForm().force(kProbeCoreR0 * kR0));
}

TEST_CASE("a seed on a particle is not placed, elsewhere it is, and the seed count goes on", "[core][construction]") {
    const auto m = smallModel(true);
    Particles p = three();
    const Eigen::Vector3d onTop = p.pos[0] + Eigen::Vector3d(0.1, 0, 0);
    const Eigen::Vector3d free = p.pos[0] + Eigen::Vector3d(0, 3 * kR0, 0);
    const Eigen::Vector3d acrossFace = Eigen::Vector3d(1e-3, 5 * kR0, 5 * kR0);  // near a particle's image
    p.add(Eigen::Vector3d(m->box.hi.x() - 1e-3, 5 * kR0, 5 * kR0), 1, 9);
    const double near = ConstructionParams{}.deathR0 * kR0;
    CHECK(crowded(p.pos, m->box, onTop, near));
    CHECK_FALSE(crowded(p.pos, m->box, free, near));
    CHECK(crowded(p.pos, m->box, acrossFace, near));  // 2e-3 apart through the periodic face
    std::vector<ConstructionEvent> timeline(4);
    for (auto& e : timeline) e.species = 1;
    timeline[0].positionVoxels = onTop;  // no map: voxels are length units
    timeline[1].positionVoxels = free;
    timeline[2].positionVoxels = acrossFace;
    timeline[3].positionVoxels = free + Eigen::Vector3d(0.2, 0, 0);  // on the seed before it, this step
    const std::size_t before = p.size();
    Simulation sim(m, std::move(p), {.construction = Construction({}, timeline, 1)});
    sim.step();  // the timeline's seeds at step 0
    REQUIRE(sim.particles().size() == before + 1);
    CHECK((sim.particles().pos.back() - free).norm() < 0.1);  // placed, then one step of motion
    CHECK(sim.construction().seedCount() == 4);
}

TEST_CASE("positions wrap into the box, from lo up to but not including hi, along periodic axes only", "[core][box]") {
    Box b;
    b.lo = {-1, 0, 2};
    b.hi = {3, 5, 4};
    b.periodic = {true, true, false};
    CHECK(b.wrap({3.25, -0.5, 7}) == Eigen::Vector3d(-0.75, 4.5, 7));
    CHECK(b.wrap({-1, 0, 2}) == Eigen::Vector3d(-1, 0, 2));
    const Eigen::Vector3d edge = b.wrap({-1 - 1e-17, 5 + 1e-15, 0});
    CHECK(edge.x() >= -1);
    CHECK(edge.x() < 3);
    CHECK(edge.y() >= 0);
    CHECK(edge.y() < 5);
    const Eigen::Vector3d w = b.wrap({1e6 + 0.3, 12.5, 3});
    CHECK(w.x() >= -1);
    CHECK(w.x() < 3);
    CHECK(w.y() == Approx(2.5));
}
