// Construction across ranks: the torus bag built by births and deaths at whatever rank count
// mpiexec gave makes the same particles, with the same ids, as a single process; ids stay
// unique; each rank holds only its window of the gradient map.
#include "OneProcessRun.hpp"
#include "RankRun.hpp"
#include "TestUtil.hpp"
#include "app/scene/RunStart.hpp"
#include "parallel/Commands.hpp"
#include "parallel/MpiExchange.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <set>

using namespace bop;
using parallel::CartComm;
using parallel::Command;
using testing::RankRun;

namespace {

// The torus scene with surface and volume growing from step 0, the single-process run built.
struct TorusBuild {
    app::Scene scene;
    std::unique_ptr<test::OneProcessRun> serialRun;
    core::Simulation* serial = nullptr;  // serialRun's
};

TorusBuild torus(long long steps) {
    TorusBuild b;
    b.scene = app::loadScene(test::sourceDir() + "/config/scenes/torus.toml");
    using A = core::ConstructionEvent::Action;
    b.scene.timeline = {{0, A::Seed, 1, {}}, {0, A::BirthOn, 1, {}}, {0, A::Seed, 2, {}}, {0, A::BirthOn, 2, {}}};
    b.serialRun = std::make_unique<test::OneProcessRun>(b.scene);
    b.serial = &**b.serialRun;
    b.serial->run(steps);
    return b;
}

// The decomposed run's start: the scene's construction, the map windows from the serial run's cache.
core::SimulationOptions optionsFor(const TorusBuild& b) {
    core::SimulationOptions o;
    o.construction = core::Construction(b.scene.construction, b.serialRun->timeline(), b.scene.model->speciesCount());
    o.map = b.serialRun->mapSource();
    o.params = b.scene.params;
    return o;
}

}  // namespace

TEST_CASE("the torus built across ranks has the single process's particles and ids", "[mpi][construction]") {
    const long long steps = 800;
    TorusBuild b = torus(steps);
    const core::Particles& expected = b.serial->particles();
    REQUIRE(b.serial->construction().totals().births > 300);  // the test builds something

    const CartComm comm(MPI_COMM_WORLD, b.serialRun->model()->box);
    RankRun run(b.serialRun->model(), core::Particles{}, optionsFor(b));
    run.run(steps);
    const core::Particles got = run.gather();

    std::set<std::uint64_t> ids(got.id.begin(), got.id.end());
    CHECK(ids.size() == got.size());  // none duplicated
    std::set<std::uint64_t> want(expected.id.begin(), expected.id.end());
    CHECK(ids == want);
    CHECK(run.construction().totals().births == b.serial->construction().totals().births);
    CHECK(run.construction().totals().deaths == b.serial->construction().totals().deaths);
    // Same particles, positions agreeing to round-off grown over the run.
    std::map<std::uint64_t, std::size_t> at;
    for (std::size_t i = 0; i < expected.size(); ++i) at[expected.id[i]] = i;
    double worst = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const auto it = at.find(got.id[i]);
        if (it == at.end()) continue;
        CHECK(got.species[i] == expected.species[it->second]);
        worst = std::max(worst, (got.pos[i] - expected.pos[it->second]).norm());
    }
    INFO("largest position difference " << worst << " (simulation length units)");
    CHECK(worst < 1e-8);
}

TEST_CASE("each rank holds only its window of the gradient map", "[mpi][construction]") {
    TorusBuild b = torus(0);
    const CartComm comm(MPI_COMM_WORLD, b.serialRun->model()->box);
    RankRun run(b.serialRun->model(), core::Particles{}, optionsFor(b));
    const std::vector<double> bytes = comm.allGather(std::vector<double>{double(run.simulation().mapBytes())});
    const GradientMap map = b.serialRun->wholeMap();
    const double whole = double(bop::gradientMapBytes(map));
    double sum = 0, largest = 0;
    for (double x : bytes) sum += x, largest = std::max(largest, x);
    if (comm.size() == 1)
        CHECK(largest <= whole);  // one window: the whole grid, the named surface
    else
        CHECK(largest < whole);
    // Windows overlap only by their margins: together they hold at most a few times the map.
    CHECK(sum < 4.0 * whole);
    // Every rank's window answers like the whole map where its particles can be.
    const GradientMap& crop = *run.simulation().mapInForce().map();
    const core::Box& sub = run.simulation().mapInForce().region;
    const double h = core::kR0 / map.r0Voxels;
    std::size_t checked = 0;
    for (std::size_t v = 0; v < crop.occ.size(); ++v) {
        const Eigen::Vector3i c = crop.wholeCoords(v);
        const Eigen::Vector3d centre = (c.cast<double>() + Eigen::Vector3d::Constant(0.5)) * h;
        if (((centre - sub.lo).array() < -h).any() || ((centre - sub.hi).array() > h).any()) continue;
        const std::size_t w = map.dims().index(c.x(), c.y(), c.z());
        REQUIRE(crop.occ[v] == map.occ[w]);
        REQUIRE(crop.delta(v) == map.delta(w));
        REQUIRE(crop.nearestSurface(v).cpWeight == map.nearestSurface(w).cpWeight);
        ++checked;
    }
    CHECK(checked > 0);
}

TEST_CASE("seed and birth commands sent to rank 0 build the same bag as the timeline", "[mpi][construction]") {
    const long long steps = 120;
    TorusBuild b = torus(steps);
    const CartComm comm(MPI_COMM_WORLD, b.serialRun->model()->box);
    core::SimulationOptions o = optionsFor(b);
    o.construction = core::Construction(b.scene.construction, {}, b.scene.model->speciesCount());
    RankRun run(b.serialRun->model(), core::Particles{}, std::move(o));
    const core::Construction timeline(b.scene.construction, b.serialRun->timeline(), b.scene.model->speciesCount());
    if (comm.rank() == 0)
        for (int s : {1, 2}) {
            // the seed's map: the whole grid
            run.submit(core::SeedCommand{
                s, timeline.defaultSeedPosition(b.serial->model(), b.serial->mapInForce().map().get(), s)});
            run.submit(core::BirthCommand{s, true});
        }
    run.run(steps);
    const core::Particles got = run.gather();
    // A commanded seed at the default position lands where the timeline's would (to the
    // round-off of a voxel-unit round trip), so the bag grows the same.
    CHECK(got.size() == b.serial->particles().size());
    std::set<std::uint64_t> ids(got.id.begin(), got.id.end());
    CHECK(ids.size() == got.size());
    CHECK(std::set<std::uint64_t>(b.serial->particles().id.begin(), b.serial->particles().id.end()) == ids);
}

TEST_CASE("deaths across ranks take the single process's victims and keep ids unique", "[mpi][construction]") {
    // Pairs closer than the death distance straddle the subdomain faces of a periodic box and
    // drift across them; no pair forces, so every death is decided by positions alone.
    auto m = std::make_shared<core::Model>();
    m->species.assign(3, core::Species{});
    m->species[1].kind = core::ParticleKind::Surface;
    m->species[2].kind = core::ParticleKind::Volume;
    core::Params none(2);  // no pair forces
    none.lj = core::WeightMatrix(2, 0.0);
    m->box.hi = Eigen::Vector3d(12, 10, 8) * core::kR0;
    m->box.periodic = {true, true, true};
    m->integration.dt = 0.05;
    core::Particles all;
    std::uint64_t id = 0;
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 10; ++j)
            for (int k = 0; k < 8; ++k) {
                const Eigen::Vector3d x = Eigen::Vector3d(i + 0.02 * j, j + 0.03 * k, k + 0.05 * i) * core::kR0;
                const std::size_t a = all.add(x, 1 + (i + j + k) % 2, id++);
                all.vel[a] =
                    Eigen::Vector3d(0.3 * std::sin(i + 2.0 * k), 0.2 * std::cos(j + k), 0.25 * std::sin(3.0 * j));
                if ((i * 7 + j * 3 + k) % 3) continue;  // a close partner for a third of them
                const std::size_t b =
                    all.add(x + Eigen::Vector3d(0.2, 0.25 * std::sin(i), 0.3) * core::kR0, 1 + (i + k) % 2, id++);
                all.vel[b] = -all.vel[a];
            }
    core::ConstructionParams params;
    params.everySteps = 5;
    using A = core::ConstructionEvent::Action;
    // Checks run and both species may die (only species whose birth is on lose particles); no map, no births.
    const std::vector<core::ConstructionEvent> timeline{{0, A::BirthOn, 1, {}}, {0, A::BirthOn, 2, {}}};
    const long long steps = 200;
    core::Simulation serial(m, all, {.construction = core::Construction(params, timeline, 2), .params = none});
    serial.run(steps);
    REQUIRE(serial.construction().totals().deaths > 100);

    const CartComm comm(MPI_COMM_WORLD, m->box);
    core::SimulationOptions o;
    o.construction = core::Construction(params, timeline, 2);
    o.params = none;
    RankRun run(m, all, std::move(o));
    run.run(steps);
    const core::Particles got = run.gather();
    CHECK(run.construction().totals().deaths == serial.construction().totals().deaths);
    const std::set<std::uint64_t> ids(got.id.begin(), got.id.end());
    CHECK(ids.size() == got.size());
    CHECK(ids == std::set<std::uint64_t>(serial.particles().id.begin(), serial.particles().id.end()));
}

TEST_CASE("a run that reads its map windows from the cache file builds the same bag", "[mpi][construction]") {
    const long long steps = 500;
    TorusBuild b = torus(steps);
    const CartComm comm(MPI_COMM_WORLD, b.serialRun->model()->box);
    test::TempDir dir("decomposed-cache");
    // Each rank keeps its own scene, as bop-server's ranks do; rank 0 writes the cache.
    app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/torus.toml");
    scene.timeline = b.scene.timeline;
    std::string cache = dir.file("map.bopgm");
    std::vector<double> path(cache.begin(), cache.end());
    comm.broadcast(path);  // one file for all ranks (TempDir names differ per process)
    cache.assign(path.begin(), path.end());
    app::RunStart start = app::startRun(scene, cache, "", comm.rank() == 0, [&] { comm.allTrue(true); });
    CHECK(!scene.model->map);  // no rank holds the whole map
    RankRun run(start.model, start.particles, std::move(start.options));
    run.run(steps);
    const core::Particles got = run.gather();
    const std::set<std::uint64_t> ids(got.id.begin(), got.id.end());
    CHECK(ids == std::set<std::uint64_t>(b.serial->particles().id.begin(), b.serial->particles().id.end()));
    double worst = 0;
    std::map<std::uint64_t, Eigen::Vector3d> want;
    for (std::size_t i = 0; i < b.serial->particles().size(); ++i)
        want[b.serial->particles().id[i]] = b.serial->particles().pos[i];
    for (std::size_t i = 0; i < got.size(); ++i)
        if (want.count(got.id[i])) worst = std::max(worst, (want[got.id[i]] - got.pos[i]).norm());
    CHECK(worst < 1e-8);
}

TEST_CASE("a cut across the subdomain faces: every rank's map and the particles as one process's",
          "[mpi][construction][cut]") {
    const long long built = 600, after = 200;
    TorusBuild b = torus(built);
    const core::Box& box = b.serialRun->model()->box;
    const Eigen::Vector3d c = 0.5 * (box.lo + box.hi);
    // A blade through the middle of the box along x, across the faces of every rank grid.
    const core::CutCommand cut{{box.lo.x(), c.y(), c.z()}, {box.hi.x(), c.y(), c.z()}, 1.5 * kR0};
    const CartComm comm(MPI_COMM_WORLD, box);
    RankRun run(b.serialRun->model(), core::Particles{}, optionsFor(b));
    run.run(built);
    b.serial->submit(cut);
    if (comm.rank() == 0) run.submit(cut);
    b.serial->run(after);
    run.run(after);
    REQUIRE(b.serial->lastCut().removed > 0);
    CHECK(run.simulation().lastCut().removed == b.serial->lastCut().removed);
    CHECK(run.simulation().lastCut().converted == b.serial->lastCut().converted);
    // Each rank's window of the edited map is the single process's edited map there.
    const GradientMap& mine = *run.simulation().mapInForce().map();
    const bop::VoxelWindow w{mine.origin,
                             mine.origin + Eigen::Vector3i(mine.dims().nx, mine.dims().ny, mine.dims().nz)};
    const GradientMap theirs = bop::cropGradientMap(*b.serial->mapInForce().map(), w);
    CHECK(mine.occ == theirs.occ);
    CHECK(mine.nearest == theirs.nearest);
    REQUIRE(mine.surface.size() == theirs.surface.size());
    std::size_t same = 0;
    for (std::size_t s = 0; s < mine.surface.size(); ++s)
        same += mine.surface[s].voxel == theirs.surface[s].voxel &&
                mine.surface[s].normal == theirs.surface[s].normal &&
                mine.surface[s].cpWeight == theirs.surface[s].cpWeight;
    CHECK(same == mine.surface.size());
    // The particles: the same ids, positions to round-off.
    const core::Particles got = run.gather();
    const core::Particles& expected = b.serial->particles();
    REQUIRE(got.size() == expected.size());
    double worst = 0;
    std::size_t sameSpecies = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        REQUIRE(got.id[i] == expected.id[i]);
        sameSpecies += got.species[i] == expected.species[i];
        worst = std::max(worst, (got.pos[i] - expected.pos[i]).norm());
    }
    INFO("largest position difference " << worst << " (simulation length units)");
    CHECK(sameSpecies == got.size());
    CHECK(worst < 1e-8);
}
