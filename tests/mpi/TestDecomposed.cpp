// The decomposed run against the single process, at whatever rank count mpiexec gave: forces of
// a frozen configuration, ids through many subdomain crossings, bit-identical repeats, and an
// undamped LJ cluster's trajectory and energy.
#include "RankRun.hpp"
#include "core/Simulation.hpp"
#include "parallel/Commands.hpp"
#include "parallel/MpiExchange.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace bop;
using namespace bop::core;
using parallel::CartComm;
using parallel::Command;
using testing::RankRun;

namespace {

// Species 1 surface, 2 and 3 volume; asymmetric LJ weights between 2 and 3.
std::shared_ptr<Model> mixedModel(bool periodic, const Eigen::Vector3d& sizeR0) {
    auto m = std::make_shared<Model>();
    m->species.assign(4, Species{});
    m->species[1].kind = ParticleKind::Surface;
    m->species[2].kind = m->species[3].kind = ParticleKind::Volume;
    m->box.hi = sizeR0 * kR0;
    m->box.periodic = {periodic, periodic, periodic};
    m->integration.dt = 0.01;
    return m;
}

// mixedModel's weights (the oriented ones 0.3, or none) and drags (beta_v and beta_tau alike).
Params mixedParams(double drag, bool oriented = true) {
    Params w(3);
    for (auto& d : w.drag) d = {drag, drag};
    w.lj(2, 3) = 0.6;
    w.lj(3, 2) = 1.4;
    w.coNormal = w.coPlanar = WeightMatrix(3, oriented ? 0.3 : 0.0);
    return w;
}

// Distance between two positions of one particle, the nearest periodic image: one process wraps a
// particle that crosses a periodic face into the box at once, ranks when they next migrate
// particles, so the two runs may hold it a box length apart (core/Exchange.cpp).
double separation(const Model& m, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    Eigen::Vector3d r = a - b;
    const Eigen::Vector3d L = m.box.size();
    for (int k = 0; k < 3; ++k)
        if (m.box.periodic[std::size_t(k)]) r[k] -= L[k] * std::round(r[k] / L[k]);
    return r.norm();
}

// Random particles at least 0.8 r0 apart (the same on every rank: a fixed seed).
Particles scatter(const Model& m, int n, std::uint32_t seed, double speed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::normal_distribution<double> g(0, speed);
    Particles p;
    const Eigen::Vector3d L = m.box.size();
    for (int tries = 0; int(p.size()) < n && tries < 100 * n; ++tries) {
        const Eigen::Vector3d x = m.box.lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(L);
        bool ok = true;
        for (const auto& y : p.pos) {
            Eigen::Vector3d r = x - y;
            for (int a = 0; a < 3; ++a)
                if (m.box.periodic[std::size_t(a)]) r[a] -= L[a] * std::round(r[a] / L[a]);
            ok = ok && r.norm() > 0.8 * kR0;
        }
        if (!ok) continue;
        const Eigen::Vector3d axis = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        const std::size_t i =
            p.add(x, 1 + int(p.size() % 3), 1000 + p.size(), Eigen::Quaterniond(Eigen::AngleAxisd(3 * u(rng), axis)));
        p.vel[i] = Eigen::Vector3d(g(rng), g(rng), g(rng));
    }
    return p;
}

// Largest force or torque difference over the largest force (at least 1), particle by particle;
// `got` comes from gather(), sorted by id like `expected` (scatter() numbers ids in order).
double forceDifference(const Particles& expected, const Particles& got) {
    REQUIRE(got.size() == expected.size());
    double worst = 0, maxF = 1;
    for (std::size_t i = 0; i < expected.size(); ++i) {
        REQUIRE(got.id[i] == expected.id[i]);
        maxF = std::max(maxF, expected.force[i].norm());
        worst =
            std::max({worst, (got.force[i] - expected.force[i]).norm(), (got.torque[i] - expected.torque[i]).norm()});
    }
    return worst / maxF;
}

}  // namespace

TEST_CASE("forces on every particle equal the single process's for a frozen configuration", "[mpi]") {
    for (const auto& [periodic, mixedPrecision] :
         {std::pair{true, false}, {false, false}, {true, true}, {false, true}}) {
        auto m = mixedModel(periodic, Eigen::Vector3d(14, 11, 9));
        m->integration.mixedPrecision = mixedPrecision;  // both in float lanes
        const Params w = mixedParams(1.0);
        Particles all = scatter(*m, 500, 3, 0.0);
        ForceField single(*m, w, m->map != nullptr);
        ForceStats ref;
        single.compute(*m, core::wholeMapOf(*m), ProbeState{}, all, ref);
        CartComm comm(MPI_COMM_WORLD, m->box);
        RankRun run(m, all, {.params = w});
        const double worst = forceDifference(all, run.gather());
        const auto t = run.totals();
        INFO("periodic " << periodic << (mixedPrecision ? ", mixed precision" : "") << ", " << comm.size()
                         << " ranks, grid " << comm.dims()[0] << "x" << comm.dims()[1] << "x" << comm.dims()[2]
                         << ": largest relative force difference " << worst);
        // Each mode agrees to its own rounding: a rank may list a pair the other way round (j's
        // row, not i's), which changes the last bits of its terms, in float lanes float's.
        const double rounding = mixedPrecision ? 1e-6 : 1e-12;
        CHECK(worst < rounding);
        CHECK(t.pairEnergy == Approx(ref.pairEnergy).epsilon(rounding));
        CHECK(t.virial == Approx(ref.virial).epsilon(rounding));
        CHECK(t.particles == double(all.size()));
    }
}

TEST_CASE("no particle is lost or duplicated over 1,000 steps of subdomain crossings", "[mpi]") {
    auto m = mixedModel(true, Eigen::Vector3d(12, 10, 9));
    const Params w = mixedParams(0.0, false);
    Particles all = scatter(*m, 300, 7, 0.0);
    for (std::size_t i = 0; i < all.size(); ++i)  // a wind that carries everything across the faces
        all.vel[i] = Eigen::Vector3d(0.8, 0.5 - 0.3 * double(i % 2), 0.4 * double(i % 3) - 0.4);
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    run.run(1000);
    const Particles got = run.gather();
    std::vector<std::uint64_t> before(all.id), after(got.id);
    std::sort(before.begin(), before.end());
    const std::vector<double> moved = comm.allGather(std::vector<double>{double(run.exchange().counts().migrations)});
    double migrations = 0;
    for (double v : moved) migrations += v;
    INFO(comm.size() << " ranks; particles here at the end " << run.simulation().particles().size() << "; "
                     << migrations << " migrations in " << run.simulation().rebuilds() << " rebuilds");
    CHECK(after == before);                          // sorted by id, so duplicates or losses would show
    CHECK((migrations > 150) == (comm.size() > 1));  // most of the 300 particles crossed a face
    const double travelled = (got.pos[0] - all.pos[0]).norm();
    CHECK(travelled > 0);
}

TEST_CASE("two runs at the same rank count are bit-identical", "[mpi]") {
    auto m = mixedModel(true, Eigen::Vector3d(12, 10, 9));
    const Params w = mixedParams(0.5);
    const Particles all = scatter(*m, 300, 11, 0.3);
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun a(m, all, {.params = w}), b(m, all, {.params = w});
    a.run(300);
    b.run(300);
    const Particles pa = a.gather(), pb = b.gather();
    CHECK(pa.pos == pb.pos);
    CHECK(pa.vel == pb.vel);
    CHECK(a.totals().total() == b.totals().total());
}

TEST_CASE("an undamped LJ cluster follows the single-process trajectory for 200 steps", "[mpi]") {
    auto m = mixedModel(false, Eigen::Vector3d(16, 16, 16));
    const Params w = mixedParams(0.0, false);
    m->integration.dt = 0.02;
    Particles all;
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 0.05);
    for (int k = 0; k < 5; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 5; ++i) {
                const std::size_t n = all.add(Eigen::Vector3d(5.5 + i, 5.5 + j, 5.5 + k) * kR0 * 1.02,
                                              2 + (i + j + k) % 2, all.size() + 1);
                all.vel[n] = Eigen::Vector3d(g(rng), g(rng), g(rng));
            }
    Simulation single(m, all, {.construction = Construction({}, {}, 3), .params = w});
    single.run(200);
    single.refreshForces();
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    run.run(200);
    const Particles got = run.gather(), want = single.gather();  // both by id
    REQUIRE(got.size() == all.size());
    REQUIRE(got.id == want.id);
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, separation(*m, got.pos[i], want.pos[i]));
    const double eSingle = single.stats().kinetic + single.stats().forces.pairEnergy;
    INFO(comm.size() << " ranks: largest position difference " << worst << ", energies " << run.totals().total()
                     << " and " << eSingle);
    CHECK(worst < 1e-9 * kR0);
    CHECK(run.totals().total() == Approx(eSingle).epsilon(1e-10));
}

TEST_CASE("a lopsided configuration is balanced and keeps the single-process forces", "[mpi][balance]") {
    // Subdomains are at least one halo range wide (3.3 r0 here, the oriented cutoff plus skin),
    // so the crowded part must hold three of them for a 3 x 1 x 1 grid to balance.
    auto m = mixedModel(false, Eigen::Vector3d(24, 12, 10));
    const Params w = mixedParams(1.0);
    auto crowded = std::make_shared<Model>(*m);  // every particle in the lower 45% of x
    crowded->box.hi.x() = 0.45 * m->box.hi.x();
    Particles all = scatter(*crowded, 600, 13, 0.0);
    ForceField single(*m, w, m->map != nullptr);
    ForceStats ref;
    single.compute(*m, core::wholeMapOf(*m), ProbeState{}, all, ref);
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    const double before = run.counters().initialImbalance, after = run.counters().imbalance;
    const Particles got = run.gather();
    REQUIRE(got.size() == all.size());
    const double worst = forceDifference(all, got);
    INFO(comm.size() << " ranks, grid " << comm.dims()[0] << "x" << comm.dims()[1] << "x" << comm.dims()[2]
                     << ": particles per rank max/mean " << before << " with uniform cuts, " << after << " balanced");
    CHECK(worst < 1e-12);
    if (comm.dims()[0] > 1) {  // the crowding is along x
        CHECK(before > 1.5);
        CHECK(after < 1.25);
    }
    CHECK(after <= before + 1e-12);
}

TEST_CASE("the probe's forces and reaction equal the single process's", "[mpi][probe]") {
    auto m = mixedModel(true, Eigen::Vector3d(14, 11, 9));
    const Params w = mixedParams(1.0);
    Particles all = scatter(*m, 500, 17, 0.0);
    ProbeState probe;
    probe.active = true;
    probe.params = {2.0, 3.0};
    probe.position = 0.5 * (m->box.lo + m->box.hi);  // inside the material, near the middle cut
    ForceField single(*m, w, m->map != nullptr);
    ForceStats ref;
    single.compute(*m, core::wholeMapOf(*m), probe, all, ref);
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    run.setProbe(probe);
    run.refreshForces();
    const Particles got = run.gather();
    const double worst = forceDifference(all, got);
    const Eigen::Vector3d reaction = run.totals().probeReaction;
    INFO(comm.size() << " ranks: reaction " << reaction.transpose() << " against " << ref.probeReaction.transpose());
    CHECK(ref.probeReaction.norm() > 1e-3);  // the probe touches particles
    CHECK(worst < 1e-12);
    CHECK((reaction - ref.probeReaction).norm() < 1e-12 * std::max(1.0, ref.probeReaction.norm()));
}

TEST_CASE("commands submitted on rank 0 apply on every rank at the same step", "[mpi][commands]") {
    auto m = mixedModel(true, Eigen::Vector3d(14, 11, 9));
    const Params w = mixedParams(0.0);
    const Particles all = scatter(*m, 400, 19, 0.2);
    ProbeState probe;
    probe.active = true;
    probe.params = {2.0, 3.0};
    const Eigen::Vector3d centre = 0.5 * (m->box.lo + m->box.hi);
    // The single process: the probe appears at step 10 and moves at step 30; species 2 gets a
    // drag at step 40; species 2 feels species 3 more strongly from step 50.
    Simulation single(m, all, {.construction = Construction({}, {}, 3), .params = w});
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    for (int s = 0; s < 80; ++s) {
        ProbeState moved = probe;
        moved.position = centre + Eigen::Vector3d(0.1 * (s - 30), 0, 0);
        if (s == 10 || s == 30) {
            probe.position = s == 10 ? centre : moved.position;
            single.probe() = probe;
            if (comm.rank() == 0) run.submit(core::ProbeCommand{probe});
        }
        if (s == 40) {
            const Command c = core::DragCommand{2, 2.0, 1.0};
            single.submit(c);
            if (comm.rank() == 0) run.submit(c);
        }
        if (s == 50) {
            const Command c = core::WeightCommand{core::WeightTable::Lj, 2, 3, 0.9};
            single.submit(c);
            if (comm.rank() == 0) run.submit(c);
        }
        single.step();
        run.step();
    }
    run.refreshForces();
    single.refreshForces();
    const Particles got = run.gather(), want = single.gather();  // both by id
    REQUIRE(got.id == want.id);
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) worst = std::max(worst, separation(*m, got.pos[i], want.pos[i]));
    const double reaction = (run.totals().probeReaction - single.stats().forces.probeReaction).norm();
    INFO(comm.size() << " ranks: largest position difference " << worst << ", reaction difference " << reaction);
    CHECK(single.stats().forces.probeReaction.norm() > 1e-3);
    CHECK(worst < 1e-9 * kR0);
    CHECK(reaction < 1e-8);
    if (comm.rank() != 0) CHECK_THROWS_AS(run.submit(core::ProbeCommand{}), std::logic_error);
    if (comm.rank() == 0) {  // refused on rank 0 before any rank applies it
        core::WeightCommand bad{core::WeightTable::Lj, 2, 7, 0};
        CHECK_THROWS_WITH(run.submit(bad), Catch::Contains("no species 7"));
        bad.other = 3;
        bad.value = -1;
        CHECK_THROWS_WITH(run.submit(bad), Catch::Contains("0 or more"));
    }
}

TEST_CASE("a command crosses ranks as the record of its kind, and a record of no kind is refused", "[mpi][commands]") {
    const std::vector<Command> sent = {core::ProbeCommand{{true, Eigen::Vector3d(1, -2, 3.5), {1.5, 0.25}}},
                                       core::DragCommand{3, 0.5, 0.125},
                                       core::SeedCommand{2, Eigen::Vector3d(-4, 5, 6)}, core::BirthCommand{2, true},
                                       core::WeightCommand{core::WeightTable::CoPlanar, 1, 2, 0.75}};
    std::vector<parallel::CommandRecord> records;
    for (const Command& c : sent) records.push_back(parallel::recordOf(c));
    const auto bytes = core::recordBytes(records);  // what the broadcast carries
    std::vector<Command> back;
    for (const auto& r : core::recordsOf<parallel::CommandRecord>(bytes)) back.push_back(parallel::commandOf(r));
    REQUIRE(back.size() == sent.size());
    for (std::size_t k = 0; k < sent.size(); ++k) REQUIRE(back[k].index() == sent[k].index());
    const auto& probe = std::get<core::ProbeCommand>(back[0]).probe;
    CHECK((probe.active && probe.position == Eigen::Vector3d(1, -2, 3.5) && probe.params.k0 == 1.5 &&
           probe.params.k1 == 0.25));
    const auto& drag = std::get<core::DragCommand>(back[1]);
    CHECK((drag.species == 3 && drag.dragV == 0.5 && drag.dragW == 0.125));
    const auto& seed = std::get<core::SeedCommand>(back[2]);
    CHECK((seed.species == 2 && seed.position == Eigen::Vector3d(-4, 5, 6)));
    const auto& birth = std::get<core::BirthCommand>(back[3]);
    CHECK((birth.species == 2 && birth.on));
    const auto& weight = std::get<core::WeightCommand>(back[4]);
    CHECK((weight.table == core::WeightTable::CoPlanar && weight.species == 1 && weight.other == 2 &&
           weight.value == 0.75));
    parallel::CommandRecord unknown;
    unknown.kind = 9;
    CHECK_THROWS_WITH(parallel::commandOf(unknown), Catch::Contains("unknown command kind 9"));
    const parallel::CommandRecord table = parallel::recordOf(core::WeightCommand{core::WeightTable(7), 1, 1, 0});
    CHECK_THROWS_WITH(parallel::commandOf(table), Catch::Contains("weight table 7"));
}

TEST_CASE("a particle a hair below a periodic face is wrapped onto the face, not past the box", "[mpi][wrap]") {
    // -1e-17 + L rounds to L: the wrapped coordinate must become lo, where the owner lookup puts it.
    auto m = mixedModel(true, Eigen::Vector3d(14, 11, 9));
    const Params w = mixedParams(1.0);
    Particles all = scatter(*m, 400, 23, 0.0);
    all.pos[0].x() = m->box.lo.x() - 1e-17;
    ForceField single(*m, w, m->map != nullptr);
    ForceStats ref;
    single.compute(*m, core::wholeMapOf(*m), ProbeState{}, all, ref);
    CartComm comm(MPI_COMM_WORLD, m->box);
    RankRun run(m, all, {.params = w});
    const Particles got = run.gather();
    const double worst = forceDifference(all, got);
    INFO(comm.size() << " ranks: particle 0 at x = " << got.pos[0].x() << ", force difference " << worst);
    CHECK(got.pos[0].x() >= m->box.lo.x());
    CHECK(got.pos[0].x() < m->box.hi.x());
    CHECK(worst < 1e-12);
}
