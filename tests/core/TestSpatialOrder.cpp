// Particles in the neighbour list's cell order (core/SpatialOrder.hpp): sorted by cell, then id,
// whatever the order before, and a run whose particles are re-sorted as they move follows the same
// trajectory, to the last bit, as one that keeps them in their first order.
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/scene/RunStart.hpp"
#include "core/CellList.hpp"
#include "core/SpatialOrder.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <set>

using namespace bop;
using namespace bop::core;

TEST_CASE("a spatial order sorts by the list's cells, then by id, whatever the order before", "[core][order]") {
    Box box;
    box.hi = Eigen::Vector3d(20, 12, 9);
    Particles p;
    std::uint64_t id = 1000;
    for (int k = 0; k < 400; ++k) {
        const double u = double((k * 7919) % 400) / 400.0, v = double((k * 104729) % 400) / 400.0;
        p.add(Eigen::Vector3d(20 * u, 12 * v, 9 * double(k % 9) / 9.0), 1 + k % 2, id--);
    }
    p.add(Eigen::Vector3d(-5, 40, 3), 1, 7);  // outside the box: in a border cell
    Particles shuffled = p;
    std::vector<std::uint32_t> back(p.size());
    for (std::uint32_t k = 0; k < back.size(); ++k) back[k] = std::uint32_t(back.size() - 1 - k);
    reorder(shuffled, back);
    REQUIRE(shuffled.id.front() == 7);
    const Particles unsorted = p;
    const std::vector<std::uint32_t> a = spatialOrder(box, 2.0, p.pos, p.id);
    const std::vector<std::uint32_t> b = spatialOrder(box, 2.0, shuffled.pos, shuffled.id);
    reorder(p, a);
    reorder(shuffled, b);
    CHECK(p.id == shuffled.id);  // the same order from either start
    CHECK(p.pos == shuffled.pos);
    CHECK(p.species == shuffled.species);
    CHECK(std::set<std::uint64_t>(p.id.begin(), p.id.end()).size() == p.size());
    CellList cells;
    cells.build(box, 2.0, p.pos);
    std::size_t outOfOrder = 0;
    for (std::size_t k = 1; k < p.size(); ++k) {
        const int c0 = cells.cellOf(p.pos[k - 1]), c1 = cells.cellOf(p.pos[k]);
        outOfOrder += c1 < c0 || (c1 == c0 && p.id[k] < p.id[k - 1]);
    }
    CHECK(outOfOrder == 0);
    // Mean distance between particles next in memory: far below that of the order before.
    const auto path = [](const Particles& q) {
        double d = 0;
        for (std::size_t k = 1; k < q.size(); ++k) d += (q.pos[k] - q.pos[k - 1]).norm();
        return d;
    };
    INFO("path through memory: " << path(unsorted) << " before, " << path(p) << " sorted");
    CHECK(path(p) < 0.5 * path(unsorted));  // 0.34 with these points
}

TEST_CASE("a bag re-sorted as it moves follows the unsorted trajectory to the last bit", "[core][order]") {
    // The torus placed on its map: the surface particles start in hash order, far from the cells' order.
    app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/torus.toml");
    scene.timeline.clear();
    scene.placement = app::PlacementParams{};
    test::TempDir dir("spatial-order");
    app::RunStart start = app::startRun(scene, dir.file("map.bopgm"), "", true, [] {});
    REQUIRE(start.particles.size() > 1000);
    const int before = threadCount();
    std::vector<Particles> ends;
    std::vector<bool> reordered;
    for (long long every : {0LL, 7LL}) {
        setThreadCount(every == 0 ? 1 : 2);
        SimulationOptions options = start.options;
        options.sortEverySteps = every;
        Simulation sim(start.model, start.particles, options);
        sim.run(1000);
        ends.push_back(sim.particles());
        reordered.push_back(sim.particles().id != start.particles.id);
    }
    setThreadCount(before);
    CHECK_FALSE(reordered[0]);
    CHECK(reordered[1]);
    // By id: every position, velocity, orientation and spin equal to the bit.
    std::map<std::uint64_t, std::size_t> at;
    for (std::size_t i = 0; i < ends[1].size(); ++i) at[ends[1].id[i]] = i;
    REQUIRE(ends[0].size() == ends[1].size());
    std::size_t differ = 0;
    double moved = 0;
    for (std::size_t i = 0; i < ends[0].size(); ++i) {
        const std::size_t j = at.at(ends[0].id[i]);
        differ += ends[0].pos[i] != ends[1].pos[j] || ends[0].vel[i] != ends[1].vel[j] ||
                  ends[0].q[i].coeffs() != ends[1].q[j].coeffs() || ends[0].omega[i] != ends[1].omega[j];
        moved = std::max(moved, (ends[0].pos[i] - start.particles.pos[i]).norm());
    }
    INFO(ends[0].size() << " particles; the largest move " << moved);
    CHECK(differ == 0);
    CHECK(moved > 0.05);  // it moved: the comparison is of trajectories
}
