// Seeds of a bag built by birth (app/scene/PieceSeeds.hpp): 26-connected pieces, and a default
// seed event turned into one seed in every piece of its species, at the voxel the run's default
// seed would choose where the species is one piece.
#include "ShapeTestUtil.hpp"
#include "app/scene/PieceSeeds.hpp"
#include "shape/Components.hpp"

#include <catch2/catch.hpp>

#include <set>

using namespace bop;
using A = core::ConstructionEvent::Action;

TEST_CASE("a diagonal staircase is one piece with 26 neighbours and one per voxel with 6", "[shape][pieces]") {
    const Dims d{8, 8, 8};
    std::set<std::size_t> stairs;
    for (int k = 0; k < 6; ++k) stairs.insert(d.index(k, k, k / 2));  // steps across edges and corners
    const auto in = [&](std::size_t v) { return stairs.count(v) > 0; };
    const shape::Components faces = shape::findComponents(d, in);
    const shape::Components all = shape::findComponents(d, in, shape::Neighbours::All);
    CHECK(faces.sizes == std::vector<std::size_t>(6, 1));
    CHECK(all.sizes == std::vector<std::size_t>{6});
    for (std::size_t v : stairs) CHECK(all.label[v] == 1);
    CHECK(std::count(all.label.begin(), all.label.end(), 0u) == std::ptrdiff_t(d.count() - 6));
}

TEST_CASE("a default seed becomes one seed in every piece of its species", "[shape][pieces]") {
    // A solid ball and a hollow one: the hollow ball's sheet is two pieces (outside and cavity).
    const Eigen::Vector3d a(14, 14, 14), b(40, 14, 14);  // voxel units
    const double ra = 9, rb = 10, cavity = 5;
    const GradientMap map = test::mapFrom(test::depthFrom(Dims{54, 28, 28}, {[&](const Eigen::Vector3d& x) {
                                                              const double db = (x - b).norm();
                                                              return (x - a).norm() < ra || (db < rb && db > cavity);
                                                          }}),
                                          2.0, 1.5);
    const core::Model model = test::bagModel(map);
    const Eigen::Vector3d given(14.5, 14.5, 14.5);
    const std::vector<core::ConstructionEvent> timeline = {
        {0, A::Seed, 1, {}}, {0, A::BirthOn, 1, {}}, {100, A::Seed, 2, given}, {100, A::Seed, 2, {}}};
    const app::PieceSeeding s = app::seedEveryPiece(model, map, {}, timeline);

    std::vector<core::ConstructionEvent> sheet, volume;
    for (const auto& e : s.timeline) {
        if (e.action != A::Seed) continue;
        REQUIRE(e.positionVoxels);
        const std::int64_t v = map.voxelHolding(*e.positionVoxels);
        REQUIRE(v >= 0);
        CHECK(int(map.occ[std::size_t(v)]) == e.species);  // each seed on a voxel of its species
        (e.species == 1 ? sheet : volume).push_back(e);
    }
    // The order of the timeline stays: seeds, switch, the given seed, the default ones.
    REQUIRE(s.timeline.size() == 7);
    CHECK(s.timeline[3].action == A::BirthOn);
    CHECK(*s.timeline[4].positionVoxels == given);
    // Sheet: ball a's, the hollow ball's outside and its cavity's; volume: one in each ball (and
    // the given one).
    REQUIRE(sheet.size() == 3);
    REQUIRE(volume.size() == 3);
    std::multiset<int> where;  // 0: ball a, 1: hollow outside, 2: cavity side
    for (const auto& e : sheet) {
        const double db = (*e.positionVoxels - b).norm();
        where.insert((*e.positionVoxels - a).norm() < ra + 1 ? 0 : db > (rb + cavity) / 2 ? 1 : 2);
    }
    CHECK(where == std::multiset<int>{0, 1, 2});
    const auto inBallA = [&](const core::ConstructionEvent& e) { return (*e.positionVoxels - a).norm() < ra; };
    const auto inBallB = [&](const core::ConstructionEvent& e) { return (*e.positionVoxels - b).norm() < rb; };
    CHECK(((inBallA(volume[1]) && inBallB(volume[2])) || (inBallB(volume[1]) && inBallA(volume[2]))));
    CHECK(s.notes.size() == 2);  // both species have several pieces

    // One piece: the seed the run chooses without pieces, and no note.
    const GradientMap one = test::mapFrom(
        test::depthFrom(Dims{28, 28, 28}, {[&](const Eigen::Vector3d& x) { return (x - a).norm() < ra; }}), 2.0, 1.5);
    const core::Model single = test::bagModel(one);
    const core::Construction c({}, {}, 2);
    const app::PieceSeeding s1 = app::seedEveryPiece(single, one, {}, {{0, A::Seed, 1, {}}, {0, A::Seed, 2, {}}});
    REQUIRE(s1.timeline.size() == 2);
    const double h = voxelLength(one.r0Voxels);
    for (int species = 1; species <= 2; ++species)
        CHECK((*s1.timeline[std::size_t(species - 1)].positionVoxels * h - c.defaultSeedPosition(single, &one, species))
                  .norm() < 1e-12);
    CHECK(s1.notes.empty());
}
