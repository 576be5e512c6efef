// The Verlet neighbour list: every pair within range exactly once (ghost images across
// periodic faces included), forces equal to brute force while particles move, cross periodic
// faces, appear and disappear, and the LJ-only fast path against the general one.
#include "BruteForce.hpp"
#include "core/CellList.hpp"
#include "core/ForceField.hpp"
#include "core/Threads.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>

using namespace bop;
using namespace bop::core;

namespace {

std::vector<Eigen::Vector3d> randomPoints(const Box& box, int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i)
        pts.push_back(box.lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.size()));
    return pts;
}

Eigen::Vector3d minimumImage(const Box& box, Eigen::Vector3d r) {
    for (int a = 0; a < 3; ++a)
        if (box.periodic[std::size_t(a)]) r[a] -= box.size()[a] * std::round(r[a] / box.size()[a]);
    return r;
}

// Species 1 surface, 2 and 3 volume (volume-only when surface = false: species 1 is volume too).
std::shared_ptr<Model> model(bool surface, bool periodic, double boxR0) {
    auto m = std::make_shared<Model>();
    m->species.assign(4, Species{});
    for (int s = 1; s <= 3; ++s) m->species[std::size_t(s)].kind = ParticleKind::Volume;
    if (surface) m->species[1].kind = ParticleKind::Surface;
    m->species[3].alphaForceOp = 0.8;
    m->box.hi = Eigen::Vector3d(boxR0, 0.8 * boxR0, 1.1 * boxR0) * kR0;
    m->box.periodic = {periodic, periodic, periodic};
    return m;
}

// model()'s weights: the oriented ones only when it has a surface species.
Params weights(bool surface) {
    Params w(3);
    w.lj(2, 3) = 0.6;  // asymmetric: alpha_23 to 2, alpha_32 to 3
    w.lj(3, 2) = 1.4;
    w.coNormal = WeightMatrix(3, surface ? 0.3 : 0.0);
    w.coPlanar = WeightMatrix(3, surface ? 0.3 : 0.0);
    return w;
}

Particles particles(const Model& m, int n, std::uint32_t seed) {
    Particles p;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (const auto& x : randomPoints(m.box, 4 * n, seed)) {
        bool ok = true;
        for (const auto& y : p.pos) ok = ok && minimumImage(m.box, x - y).norm() > 0.75 * kR0;
        if (!ok) continue;
        const Eigen::Quaterniond q(Eigen::AngleAxisd(3 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized()));
        p.add(x, 1 + int(p.size() % 3), p.size() + 1, q);
        if (int(p.size()) == n) break;
    }
    return p;
}

// Largest difference between the field's forces and torques and brute force, relative to the
// largest brute-force force.
double bruteForceError(const Model& m, const Params& w, ForceField& field, Particles& p, bool energies) {
    const test::BruteForceComparison c = test::compareWithBruteForce(m, w, field, p, energies);
    REQUIRE(c.field.pairsInRange == c.brute.pairsInRange);
    REQUIRE(c.field.orientedPairsInRange == c.brute.orientedPairsInRange);
    CHECK(c.field.virial == Approx(c.brute.virial).epsilon(1e-11));
    return std::max(c.forceError, c.torqueError) / std::max(1.0, c.maxForce);
}

}  // namespace

TEST_CASE("the neighbour list holds every pair within range exactly once", "[core][neighbours]") {
    for (bool periodic : {true, false}) {
        Box box;
        box.lo = Eigen::Vector3d(-3, 1, 2);
        box.hi = box.lo + Eigen::Vector3d(14, 11, 17);
        box.periodic = {periodic, periodic, periodic};
        const double range = 3.3;
        const auto pts = randomPoints(box, 900, periodic ? 7 : 8);
        // The wide pairs: two points in three, to a range that reaches farther.
        NeighbourList::Wide wide;
        wide.range = 4.9;
        wide.member.resize(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) wide.member[i] = i % 3 != 0;
        NeighbourList list;
        list.build(box, range, pts, {}, &wide);
        REQUIRE(list.update(box, pts, 0.1));
        std::set<std::pair<std::uint32_t, std::uint32_t>> found;
        std::size_t duplicates = 0;
        const NeighbourList::Pairs& pairs = list.pairs();
        for (std::size_t e = 0; e < list.entryCount(); ++e)
            for (std::uint32_t k = pairs.start[e]; k < pairs.start[e + 1]; ++k) {
                const std::uint32_t i = list.owner()[e], j = list.owner()[pairs.nbr[k]];
                duplicates += !found.insert({std::min(i, j), std::max(i, j)}).second;
            }
        std::set<std::pair<std::uint32_t, std::uint32_t>> expected, expectedWide, foundWide;
        for (std::uint32_t i = 0; i < pts.size(); ++i)
            for (std::uint32_t j = i + 1; j < pts.size(); ++j) {
                const double d = minimumImage(box, pts[j] - pts[i]).norm();
                if (d < range) expected.insert({i, j});
                if (d < wide.range && wide.member[i] && wide.member[j]) expectedWide.insert({i, j});
            }
        const NeighbourList::Pairs& widePairs = list.widePairs();
        std::size_t wideDuplicates = 0, wideNotSmaller = 0;
        for (std::uint32_t e = 0; e < list.entryCount(); ++e)
            for (std::uint32_t k = widePairs.start[e]; k < widePairs.start[e + 1]; ++k) {
                const std::uint32_t i = list.owner()[e], j = list.owner()[widePairs.nbr[k]];
                wideNotSmaller += widePairs.nbr[k] <= e;
                wideDuplicates += !foundWide.insert({std::min(i, j), std::max(i, j)}).second;
            }
        INFO("periodic " << periodic << ": " << expected.size() << " pairs, " << expectedWide.size() << " wide, "
                         << list.ghostCount() << " ghosts");
        CHECK(duplicates == 0);
        CHECK(found == expected);
        CHECK(expected.size() > 5000);
        CHECK(wideDuplicates == 0);
        CHECK(wideNotSmaller == 0);
        CHECK(foundWide == expectedWide);
        CHECK(expectedWide.size() > 5000);
        CHECK(list.range() == wide.range);

        // With groups (two bags' surfaces, say) the wide pairs are those the table joins only.
        NeighbourList::Wide grouped = wide;
        grouped.side = 3;
        grouped.together = {0, 0, 0, 0, 1, 0, 0, 0, 1};  // group 1 with 1, 2 with 2
        grouped.group.resize(pts.size());
        for (std::size_t i = 0; i < pts.size(); ++i) grouped.group[i] = std::uint8_t(1 + i % 2);
        NeighbourList apart;
        apart.build(box, range, pts, {}, &grouped);
        std::set<std::pair<std::uint32_t, std::uint32_t>> foundGrouped, expectedGrouped;
        for (const auto& [i, j] : expectedWide)
            if (i % 2 == j % 2) expectedGrouped.insert({i, j});
        const NeighbourList::Pairs& groupedPairs = apart.widePairs();
        for (std::uint32_t e = 0; e < apart.entryCount(); ++e)
            for (std::uint32_t k = groupedPairs.start[e]; k < groupedPairs.start[e + 1]; ++k) {
                const std::uint32_t i = apart.owner()[e], j = apart.owner()[groupedPairs.nbr[k]];
                foundGrouped.insert({std::min(i, j), std::max(i, j)});
            }
        CHECK(foundGrouped == expectedGrouped);
        CHECK(expectedGrouped.size() < 0.6 * double(expectedWide.size()));
        CHECK((list.ghostCount() > 0) == periodic);
    }
}

TEST_CASE("a row lists its neighbours within the tier first", "[core][neighbours]") {
    for (bool periodic : {false, true}) {  // the branch-free rows of a plain list, and the general ones
        Box box;
        box.hi = Eigen::Vector3d(13, 12, 15);
        box.periodic = {periodic, periodic, periodic};
        const auto pts = randomPoints(box, 800, 11);
        NeighbourList list;
        list.build(box, 3.3, pts, {}, nullptr, nullptr, 2.1);
        std::size_t near = 0, far = 0, misplaced = 0;
        const NeighbourList::Pairs& pairs = list.pairs();
        for (std::size_t e = 0; e < list.entryCount(); ++e) {
            bool seenFar = false;
            for (std::uint32_t k = pairs.start[e]; k < pairs.start[e + 1]; ++k) {
                const bool isNear = (list.positions()[pairs.nbr[k]] - list.positions()[e]).norm() < 2.1;
                misplaced += isNear && seenFar;
                seenFar = seenFar || !isNear;
                (isNear ? near : far) += 1;
            }
        }
        INFO("periodic " << periodic << ": " << near << " pairs within the tier, " << far << " beyond");
        CHECK(misplaced == 0);
        CHECK(near > 1000);
        CHECK(far > 1000);
    }
}

TEST_CASE("a cell's forward ranges cover its half stencil, by offsets away from the faces", "[core][neighbours]") {
    Box box;
    box.hi = Eigen::Vector3d(20, 13, 17);  // 6 x 3 x 5 cells of 3.3: the axes in another order
    const auto pts = randomPoints(box, 1500, 5);
    CellList cells;
    cells.build(box, 3.3, pts);
    const auto offsets = cells.forwardOffsets(1);
    std::size_t interior = 0;
    std::vector<std::array<std::uint32_t, 2>> ranges;
    std::array<CellList::Neighbour, 14> stencil;
    for (int c = 0; c < cells.cellCount(); ++c) {
        cells.forwardRanges(c, 1, ranges);
        std::set<std::uint32_t> fromRanges, fromStencil;
        for (const auto& [first, last] : ranges)
            for (std::uint32_t k = first; k < last; ++k) fromRanges.insert(k);
        const int m = cells.halfStencil(c, stencil);
        for (int s = 0; s < m; ++s)
            for (std::uint32_t k = cells.start(stencil[std::size_t(s)].cell);
                 k < cells.start(stencil[std::size_t(s)].cell + 1); ++k)
                fromStencil.insert(k);
        INFO("cell " << c);
        CHECK(fromRanges == fromStencil);
        REQUIRE(!ranges.empty());
        CHECK(ranges[0][0] == cells.start(c));  // the cell's own entries open the first range
        if (!cells.interior(c, 1)) continue;
        ++interior;
        REQUIRE(offsets.size() == ranges.size());
        for (std::size_t r = 0; r < ranges.size(); ++r) {
            CHECK(cells.start(c + offsets[r][0]) == ranges[r][0]);
            CHECK(cells.start(c + offsets[r][1] + 1) == ranges[r][1]);
        }
    }
    CHECK(interior == 4 * 1 * 3);
    Box periodic = box;
    periodic.periodic = {true, false, false};
    cells.build(periodic, 3.3, pts);
    CHECK_THROWS_WITH(cells.forwardRanges(0, 1, ranges), Catch::Contains("periodic"));
}

TEST_CASE("the neighbour list is the same at 1, 2 and 3 threads, and complete", "[core][neighbours][threads]") {
    // Enough entries that the build runs on the threads (blocks of cells joined in order).
    for (bool periodic : {true, false}) {
        Box box;
        box.hi = Eigen::Vector3d(40, 26, 12);  // flat: the cells' slowest axis is x
        box.periodic = {periodic, periodic, periodic};
        const auto pts = randomPoints(box, 7000, periodic ? 11 : 12);
        std::vector<Eigen::Vector3d> halo;  // ghosts beyond the faces of the open box
        if (!periodic)
            for (const auto& x : randomPoints(box, 600, 13)) halo.push_back(x + Eigen::Vector3d(0, 0, 13.5));
        NeighbourList::Wide wide;
        wide.range = 4.9;
        wide.member.resize(pts.size() + halo.size());
        for (std::size_t i = 0; i < wide.member.size(); ++i) wide.member[i] = i % 3 != 0;
        std::vector<NeighbourList> lists(3);
        for (int t = 1; t <= 3; ++t) {
            setThreadCount(t);
            lists[std::size_t(t - 1)].build(box, 3.3, pts, halo, &wide);
        }
        setThreadCount(1);
        const auto sets = [](const NeighbourList& l) {
            return std::vector{&l.pairs(), &l.haloPairs(), &l.widePairs(), &l.wideHaloPairs()};
        };
        for (int t = 2; t <= 3; ++t)
            for (std::size_t k = 0; k < 4; ++k) {
                INFO("periodic " << periodic << ", " << t << " threads, pair set " << k);
                CHECK(sets(lists[std::size_t(t - 1)])[k]->start == sets(lists[0])[k]->start);
                CHECK(sets(lists[std::size_t(t - 1)])[k]->nbr == sets(lists[0])[k]->nbr);
            }
        std::size_t expected = 0, expectedHalo = 0;  // pairs within range, by brute force
        for (std::size_t i = 0; i < pts.size(); ++i) {
            for (std::size_t j = i + 1; j < pts.size(); ++j)
                expected += minimumImage(box, pts[j] - pts[i]).norm() < 3.3;
            for (const auto& g : halo) expectedHalo += (g - pts[i]).norm() < 3.3;
        }
        CHECK(lists[2].entryCount() > 4096);
        CHECK(lists[2].pairs().size() == expected);
        CHECK(lists[2].haloPairs().size() == expectedHalo);
        CHECK(lists[2].widePairs().size() > 0);
        CHECK((expectedHalo > 0) == !periodic);
    }
}

TEST_CASE("a periodic box narrower than twice the neighbour range is refused", "[core][neighbours]") {
    Box box;
    box.hi = Eigen::Vector3d(10, 6, 10);
    box.periodic = {true, true, true};
    NeighbourList list;
    CHECK_THROWS_WITH(list.build(box, 3.3, randomPoints(box, 10, 1)), Catch::Contains("twice the neighbour range"));
}

TEST_CASE("forces match brute force as particles drift across periodic faces and are replaced", "[core][neighbours]") {
    for (bool surface : {true, false}) {
        for (bool periodic : {true, false}) {
            auto m = model(surface, periodic, 9.0);
            Particles p = particles(*m, 320, periodic ? 3 : 4);
            ForceField field(*m, weights(surface), m->map != nullptr);
            std::mt19937 rng(11);
            std::normal_distribution<double> g(0, 0.01 * kR0);  // per move, well below skin / 2
            const Eigen::Vector3d L = m->box.size();
            double worst = 0;
            int wraps = 0;
            for (int it = 0; it < 60; ++it) {
                for (auto& x : p.pos) {
                    x += Eigen::Vector3d(g(rng), g(rng), g(rng)) + Eigen::Vector3d(0.02, 0.015, 0.0) * kR0;
                    for (int a = 0; a < 3 && periodic; ++a)
                        if (x[a] < m->box.lo[a] || x[a] >= m->box.hi[a]) {
                            x[a] -= L[a] * std::floor((x[a] - m->box.lo[a]) / L[a]);
                            ++wraps;
                        }
                }
                if (it == 20) {  // a death and a birth in one step: same count, other particles
                    std::vector<char> die(p.size(), 0);
                    die[5] = 1;
                    p.removeIf(die);
                    p.add(m->box.lo + 0.5 * L, 2, 10000);
                }
                worst = std::max(worst, bruteForceError(*m, weights(surface), field, p, it % 3 == 0));
            }
            INFO("surface " << surface << ", periodic " << periodic << ": " << field.pairs().neighbours().builds()
                            << " list builds, " << wraps << " wraps");
            CHECK(worst < 1e-12);
            CHECK(field.pairs().neighbours().builds() > 2);   // rebuilt as particles drift and after the birth
            CHECK(field.pairs().neighbours().builds() < 40);  // and reused in between
            CHECK((wraps > 0) == periodic);
        }
    }
}

TEST_CASE("pruned pair lists give the whole list's forces and torques to the bit as particles drift",
          "[core][neighbours][prune]") {
    // An outer skin of 0.6 r0: the pruned copies must be pruned again many times between builds.
    Model whole = *model(true, true, 9.0), pruned = whole;
    whole.integration.skinR0 = pruned.integration.skinR0 = 0.6;
    whole.integration.pruneR0 = 0.0;
    pruned.integration.pruneR0 = 0.05;
    Particles p = particles(whole, 320, 3);
    ForceField a(whole, weights(true), false), b(pruned, weights(true), false);
    std::mt19937 rng(9);
    std::normal_distribution<double> g(0, 0.004 * kR0);  // per move
    const Eigen::Vector3d L = whole.box.size();
    std::size_t differing = 0, fewerLj = 0, fewerWide = 0;
    for (int it = 0; it < 80; ++it) {
        for (auto& x : p.pos) {
            x += Eigen::Vector3d(g(rng), g(rng), g(rng)) + Eigen::Vector3d(0.004, 0.0, -0.003) * kR0;
            for (int c = 0; c < 3; ++c) x[c] -= L[c] * std::floor((x[c] - whole.box.lo[c]) / L[c]);
        }
        Particles pa = p, pb = p;
        ForceStats sa, sb;
        a.compute(whole, core::wholeMapOf(whole), ProbeState{}, pa, sa, nullptr, it % 4 == 0);
        b.compute(pruned, core::wholeMapOf(pruned), ProbeState{}, pb, sb, nullptr, it % 4 == 0);
        for (std::size_t i = 0; i < p.size(); ++i)
            differing += pa.force[i] != pb.force[i] || pa.torque[i] != pb.torque[i];
        CHECK(sa.pairsInRange == sb.pairsInRange);
        CHECK(sa.orientedPairsInRange == sb.orientedPairsInRange);
        CHECK(sb.virial == Approx(sa.virial).epsilon(1e-13));
        CHECK(sb.pairEnergy == Approx(sa.pairEnergy).epsilon(1e-13));
        fewerLj += b.pairs().pruned().pairCount() < a.pairs().neighbours().pairCount();
        fewerWide += b.pairs().pruned().widePairCount() < a.pairs().neighbours().widePairCount();
    }
    INFO(a.pairs().neighbours().builds() << " list builds, " << b.pairs().pruned().prunes() << " prunings, last "
                                         << b.pairs().pruned().pairCount() << " of "
                                         << b.pairs().neighbours().pairCount() << " LJ pairs, "
                                         << b.pairs().pruned().widePairCount() << " of "
                                         << b.pairs().neighbours().widePairCount() << " oriented");
    CHECK(differing == 0);
    CHECK(b.pairs().neighbours().builds() == a.pairs().neighbours().builds());
    CHECK(a.pairs().pruneSkin() == 0);
    CHECK(b.pairs().pruned().prunes() > b.pairs().neighbours().builds() + 3);  // pruned again between builds
    CHECK(b.pairs().pruned().prunes() < 60);                                   // and reused in between
    CHECK(fewerLj == 80);
    CHECK(fewerWide == 80);
}

TEST_CASE("two subdomains with halos give the forces and energy of the whole box", "[core][neighbours][halo]") {
    // The decomposed run's core half: split a periodic box in x, give each half the other's
    // particles within range (shifted across the periodic x faces) as a halo.
    for (bool surface : {true, false}) {
        auto m = model(surface, true, 9.0);
        Particles all = particles(*m, 320, 5);
        ForceField whole(*m, weights(surface), m->map != nullptr);
        ForceStats ref;
        whole.compute(*m, core::wholeMapOf(*m), ProbeState{}, all, ref);
        const double L = m->box.size().x(), cut = 0.5 * (m->box.lo.x() + m->box.hi.x());
        const double range = whole.pairs().neighbours().range();
        double energy = 0, virial = 0, worst = 0, maxF = 1;
        std::size_t owned = 0;
        for (int side = 0; side < 2; ++side) {
            auto sub = std::make_shared<Model>(*m);
            sub->box.lo.x() = side == 0 ? m->box.lo.x() : cut;
            sub->box.hi.x() = side == 0 ? cut : m->box.hi.x();
            sub->box.periodic[0] = false;
            Particles mine;
            Halo halo;
            std::vector<std::size_t> index;
            for (std::size_t i = 0; i < all.size(); ++i) {
                const bool inside = all.pos[i].x() >= sub->box.lo.x() && all.pos[i].x() < sub->box.hi.x();
                if (inside) {
                    mine.add(all.pos[i], all.species[i], all.id[i], all.q[i]);
                    index.push_back(i);
                    continue;
                }
                for (double shift : {-L, 0.0, L}) {
                    const double x = all.pos[i].x() + shift;
                    if (x < sub->box.lo.x() - range || x >= sub->box.hi.x() + range) continue;
                    halo.pos.push_back(all.pos[i] + Eigen::Vector3d(shift, 0, 0));
                    halo.normal.push_back(all.normal[i]);
                    halo.species.push_back(all.species[i]);
                }
            }
            ForceField part(*sub, weights(surface), sub->map != nullptr);
            ForceStats s;
            part.compute(*sub, core::wholeMapOf(*sub), ProbeState{}, mine, s, nullptr, true, &halo);
            energy += s.pairEnergy;
            virial += s.virial;
            owned += mine.size();
            for (std::size_t k = 0; k < mine.size(); ++k) {
                maxF = std::max(maxF, all.force[index[k]].norm());
                worst = std::max({worst, (mine.force[k] - all.force[index[k]]).norm(),
                                  (mine.torque[k] - all.torque[index[k]]).norm()});
            }
            CHECK(part.pairs().neighbours().haloPairs().size() > 100);
        }
        INFO("surface species " << surface);
        CHECK(owned == all.size());
        CHECK(worst / maxF < 1e-12);
        CHECK(energy == Approx(ref.pairEnergy).epsilon(1e-12));
        CHECK(virial == Approx(ref.virial).epsilon(1e-12));
    }
}
