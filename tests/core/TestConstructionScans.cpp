// The construction's death scan on the threads: the marks of a crowd of particles are the same
// at 1, 2 and 3 threads and are the pairs' victims by the rule, found by brute force.
#include "core/ConstructionSteps.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace bop;
using namespace bop::core;

TEST_CASE("the death scan marks the same victims at 1, 2 and 3 threads, as the rule says",
          "[core][construction][threads]") {
    Model m;
    m.species.assign(3, Species{});
    m.species[1].kind = ParticleKind::Surface;
    m.species[2].kind = ParticleKind::Volume;
    m.box.hi = Eigen::Vector3d(60, 40, 20);
    Particles p;  // scattered, then a close partner for every tenth particle
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1), near(-0.4, 0.4);
    for (std::uint64_t k = 0; k < 9000; ++k) {
        const Eigen::Vector3d x = Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(m.box.size());
        p.add(x, 1 + int(k % 2), 1000 + ((k * 7919) % 9000), Eigen::Quaterniond::Identity());
        if (k % 10 == 0)
            p.add(x + Eigen::Vector3d(near(rng), near(rng), near(rng)), 1 + int(k % 3 == 0), 20000 + k,
                  Eigen::Quaterniond::Identity());
    }
    const std::size_t owned = p.size() - 300;  // the last 300 stand for another rank's ghosts
    ConstructionParams params;
    const double d = params.deathR0 * kR0;
    std::set<std::uint64_t> expected;  // by brute force: the victim of each close pair, own ones only
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            if ((p.pos[i] - p.pos[j]).squaredNorm() >= d * d || (i >= owned && j >= owned)) continue;
            const bool si = m.isSurface(p.species[i]), sj = m.isSurface(p.species[j]);
            const std::size_t victim = si != sj ? (si ? j : i) : (p.id[i] > p.id[j] ? i : j);
            if (victim < owned) expected.insert(p.id[victim]);
        }
    std::vector<std::vector<DeathMark>> marks;
    const int before = threadCount();
    for (int t = 1; t <= 3; ++t) {
        setThreadCount(t);
        marks.push_back(markDeaths(params, {m, m.box, p, owned, m.map.get()}, 42));
    }
    setThreadCount(before);
    std::set<std::uint64_t> found;
    for (const DeathMark& k : marks[0]) found.insert(k.id);
    INFO(expected.size() << " victims expected");
    CHECK(expected.size() > 300);
    CHECK(found == expected);
    CHECK(marks[0].size() == found.size());  // each victim once
    for (int t = 2; t <= 3; ++t) {
        REQUIRE(marks[std::size_t(t - 1)].size() == marks[0].size());
        for (std::size_t k = 0; k < marks[0].size(); ++k) {
            CHECK(marks[std::size_t(t - 1)][k].id == marks[0][k].id);
            CHECK(marks[std::size_t(t - 1)][k].key == marks[0][k].key);
        }
    }
}
