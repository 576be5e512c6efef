// The cluster-pair layout as built for measurement (app/tools/ClusterPairs.hpp, ClusterLjLoop.hpp;
// docs/dynamics.md, "A cluster-pair layout"): its clusters hold each of the list's pairs in one
// lane, once, and its LJ loop computes the core's LJ loop's forces, virial, energy and count on
// the same list, with several species of asymmetric weights, surface and volume kinds, periodic
// images, and an open box. The figures that decided against it come from the same code
// (scripts/bench/cluster-proto.sh): these checks keep them about the right computation.
#include "app/tools/ClusterForm.hpp"
#include "app/tools/ClusterPairs.hpp"
#include "core/FccLattice.hpp"

#include <catch2/catch.hpp>

using namespace bop;

namespace {

struct Cloud {
    core::Model model;
    core::Params params{1};
    core::Particles particles;
};

// An fcc box of `cells`^3 cells at nearest distance r0, each site moved up to 0.05 r0 per axis,
// species dealt 1..3 (3 a surface species) with asymmetric LJ weights; periodic or not.
Cloud fcc(int cells, bool periodic) {
    Cloud c;
    c.model.species.assign(4, core::Species{});
    for (int s = 1; s <= 3; ++s) c.model.species[std::size_t(s)].kind = core::ParticleKind::Volume;
    c.model.species[3].kind = core::ParticleKind::Surface;
    const double a = std::sqrt(2.0) * kR0;
    c.model.box.hi = Eigen::Vector3d::Constant(cells * a);
    c.model.box.periodic = {periodic, periodic, periodic};
    c.params = core::Params(3);
    c.params.lj(1, 2) = 0.5;
    c.params.lj(2, 1) = 1.5;
    c.params.lj(3, 1) = 0.8;
    std::uint64_t id = 0;
    for (const Eigen::Vector3d& x : test::jitteredFcc(cells, 11)) {
        c.particles.add(x + (periodic ? Eigen::Vector3d::Zero() : Eigen::Vector3d::Constant(0.1)), 1 + int(id % 3),
                        id + 1);
        ++id;
    }
    return c;
}

}  // namespace

TEST_CASE("cluster layout: each listed pair is one lane of one cluster pair", "[core][clusters]") {
    const Cloud c = fcc(5, true);
    core::NeighbourList list;
    list.build(c.model.box, 1.9 * kR0, c.particles.pos, {}, nullptr, &c.particles.id, 1.6 * kR0);
    const std::size_t ne = list.entryCount();
    tools::ClusterPairs clusters;
    clusters.build(list.pairs(), ne, std::vector<char>(ne, 1));
    REQUIRE(list.pairs().size() > 10000);
    CHECK(clusters.clusterCount() == (ne + 3) / 4);
    CHECK(clusters.laneCount() == list.pairs().size());
    std::size_t found = 0;  // every listed pair's lane is set in its cluster pair
    for (std::size_t x = 0; x < ne; ++x)
        for (std::uint32_t k = list.pairs().start[x]; k < list.pairs().start[x + 1]; ++k) {
            const std::uint32_t y = list.pairs().nbr[k], ci = std::uint32_t(x / 4), cj = y / 4;
            for (std::uint32_t e = clusters.start[ci]; e < clusters.start[ci + 1]; ++e)
                if (clusters.list[e].j == cj && (clusters.list[e].lanes >> (4 * (x % 4) + y % 4) & 1)) ++found;
        }
    CHECK(found == list.pairs().size());
    std::size_t disordered = 0;  // rows in increasing j >= i
    for (std::size_t ci = 0; ci < clusters.clusterCount(); ++ci)
        for (std::uint32_t e = clusters.start[ci]; e < clusters.start[ci + 1]; ++e)
            disordered +=
                clusters.list[e].j < ci || (e > clusters.start[ci] && clusters.list[e].j <= clusters.list[e - 1].j);
    CHECK(disordered == 0);
}

TEST_CASE("cluster layout: its LJ loop computes the core's LJ pairs to float rounding", "[core][clusters]") {
    for (const bool periodic : {true, false}) {
        const Cloud c = fcc(6, periodic);
        const tools::ClusterFormResult r = tools::measureClusterForm(c.model, c.params, c.particles, c.model.box, 1);
        INFO((periodic ? "periodic" : "open") << " box: forces " << r.forceDifference << ", virial "
                                              << r.virialDifference << ", energy " << r.energyDifference);
        CHECK(r.inRange > 5000);
        CHECK(r.sameCount);
        CHECK(r.forceDifference < 1e-5);
        CHECK(r.forceDifference > 0);  // f(r)/r in float: not double's to the bit
        CHECK(r.virialDifference < 1e-5);
        CHECK(r.energyDifference < 1e-12);  // both in double from the double r^2
        CHECK(16 * r.clusterPairs >= r.inRange);
    }
}
