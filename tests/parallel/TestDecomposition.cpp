// The rank grid's cut of the box (no MPI): uniform cuts tile the box, owner() names the
// subdomain that holds a position (wrapping periodic boxes, clamping outside closed ones), rank
// numbers follow MPI_Cart_create's z-fastest order, too-small boxes are refused by axis, and
// balance() evens out a lopsided particle distribution without making any subdomain narrower
// than the halo range.
#include "parallel/Decomposition.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>

using namespace bop;
using namespace bop::parallel;

namespace {

core::Box makeBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& size, std::array<bool, 3> periodic) {
    core::Box b;
    b.lo = lo;
    b.hi = lo + size;
    b.periodic = periodic;
    return b;
}

std::vector<Eigen::Vector3d> uniformPoints(const core::Box& box, int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i)
        pts.push_back(box.lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(box.size()));
    return pts;
}

// 90% of the points in the first fifth of the x range, 10% over the rest; y and z uniform.
std::vector<Eigen::Vector3d> lopsidedPoints(const core::Box& box, int n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const Eigen::Vector3d L = box.size();
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < n; ++i) {
        const double fx = i < n * 9 / 10 ? 0.2 * u(rng) : 0.2 + 0.8 * u(rng);
        pts.push_back(box.lo + Eigen::Vector3d(fx * L[0], u(rng) * L[1], u(rng) * L[2]));
    }
    return pts;
}

// Per axis, particle counts in `bins` equal bins across the box.
std::array<std::vector<double>, 3> histograms(const core::Box& box, const std::vector<Eigen::Vector3d>& pts, int bins) {
    std::array<std::vector<double>, 3> h;
    for (int a = 0; a < 3; ++a) {
        auto& ha = h[std::size_t(a)];
        ha.assign(std::size_t(bins), 0.0);
        const double L = box.hi[a] - box.lo[a];
        for (const auto& x : pts) {
            const int b = std::clamp(int(std::floor((x[a] - box.lo[a]) / L * bins)), 0, bins - 1);
            ha[std::size_t(b)] += 1;
        }
    }
    return h;
}

bool inside(const core::Box& b, const Eigen::Vector3d& x) {
    for (int a = 0; a < 3; ++a)
        if (x[a] < b.lo[a] || x[a] >= b.hi[a]) return false;
    return true;
}

// Euclidean distance from x to the closed box b (0 inside).
double distanceTo(const core::Box& b, const Eigen::Vector3d& x) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) d[a] = std::max({b.lo[a] - x[a], 0.0, x[a] - b.hi[a]});
    return d.norm();
}

std::vector<Coords> allCoords(const Coords& dims) {
    std::vector<Coords> cs;
    for (int i = 0; i < dims[0]; ++i)
        for (int j = 0; j < dims[1]; ++j)
            for (int k = 0; k < dims[2]; ++k) cs.push_back({i, j, k});
    return cs;
}

// Cut planes strictly increasing from box.lo to box.hi, every subdomain at least minWidth wide.
void checkCuts(const Decomposition& d, double minWidth) {
    for (int a = 0; a < 3; ++a) {
        const auto& c = d.cuts(a);
        REQUIRE(c.size() == std::size_t(d.dims()[std::size_t(a)]) + 1);
        CHECK(c.front() == d.box().lo[a]);
        CHECK(c.back() == d.box().hi[a]);
        for (std::size_t k = 1; k < c.size(); ++k) {
            INFO("axis " << a << " subdomain " << k - 1 << ": [" << c[k - 1] << ", " << c[k] << "), minWidth "
                         << minWidth);
            CHECK(c[k] > c[k - 1]);
            if (c.size() > 2) CHECK(c[k] - c[k - 1] >= minWidth - 1e-12);
        }
    }
}

}  // namespace

TEST_CASE("Uniform cuts sit at lo + L*k/n and the subdomains tile the box", "[parallel][decomposition]") {
    const auto box = makeBox({-5.0, 2.0, 1.0}, {40.0, 30.0, 21.0}, {true, false, true});
    const double minWidth = 2.5;
    for (const Coords dims : {Coords{1, 1, 1}, Coords{2, 1, 1}, Coords{3, 2, 1}, Coords{4, 3, 5}, Coords{1, 7, 2}}) {
        INFO("dims " << dims[0] << "x" << dims[1] << "x" << dims[2]);
        const Decomposition d(box, dims, minWidth);
        CHECK(d.rankCount() == dims[0] * dims[1] * dims[2]);
        for (int a = 0; a < 3; ++a) {
            const int n = dims[std::size_t(a)];
            const double L = box.hi[a] - box.lo[a];
            REQUIRE(d.cuts(a).size() == std::size_t(n) + 1);
            for (int k = 0; k <= n; ++k) CHECK(d.cuts(a)[std::size_t(k)] == Approx(box.lo[a] + L * k / n));
            CHECK(d.cuts(a).front() == box.lo[a]);
            CHECK(d.cuts(a).back() == box.hi[a]);
        }

        // Volumes add up to the box, neighbours share their faces, and the outer faces are the box's.
        double volume = 0;
        for (const auto& c : allCoords(dims)) {
            const auto s = d.subdomain(c);
            const Eigen::Vector3d size = s.size();
            volume += size.prod();
            for (int a = 0; a < 3; ++a) {
                const auto ua = std::size_t(a);
                CHECK(size[a] == Approx((box.hi[a] - box.lo[a]) / dims[ua]));
                if (c[ua] == 0) CHECK(s.lo[a] == box.lo[a]);
                if (c[ua] == dims[ua] - 1) CHECK(s.hi[a] == box.hi[a]);
                if (c[ua] + 1 < dims[ua]) {
                    Coords next = c;
                    ++next[ua];
                    CHECK(d.subdomain(next).lo[a] == s.hi[a]);
                }
                CHECK(s.periodic[ua] == (box.periodic[ua] && dims[ua] == 1));
            }
        }
        CHECK(volume == Approx(box.size().prod()).epsilon(1e-12));

        // Every point of the box lies in exactly one subdomain.
        for (const auto& x : uniformPoints(box, 500, 11)) {
            int holders = 0;
            for (const auto& c : allCoords(dims)) holders += inside(d.subdomain(c), x);
            INFO("point " << x.transpose());
            CHECK(holders == 1);
        }
    }
}

TEST_CASE("Subdomains are periodic only along unsplit periodic axes", "[parallel][decomposition]") {
    const auto box = makeBox({0, 0, 0}, {20, 20, 20}, {true, true, false});
    const Decomposition split(box, {2, 1, 1}, 3.0);
    for (const auto& c : allCoords(split.dims())) {
        const auto s = split.subdomain(c);
        CHECK_FALSE(s.periodic[0]);  // split: images across x come as halos
        CHECK(s.periodic[1]);        // one rank along periodic y: the rank wraps itself
        CHECK_FALSE(s.periodic[2]);  // the box is closed along z
    }
    const auto box2 = makeBox({0, 0, 0}, {20, 20, 20}, {true, false, true});
    const Decomposition split2(box2, {1, 1, 3}, 3.0);
    for (const auto& c : allCoords(split2.dims())) {
        const auto s = split2.subdomain(c);
        CHECK(s.periodic[0]);
        CHECK_FALSE(s.periodic[1]);
        CHECK_FALSE(s.periodic[2]);
    }
}

TEST_CASE("owner() names the subdomain whose half-open bounds hold the point", "[parallel][decomposition]") {
    const auto box = makeBox({-3.0, 4.0, -10.0}, {36.0, 25.0, 18.0}, {false, true, false});
    const double minWidth = 2.5;
    for (const Coords dims : {Coords{1, 1, 1}, Coords{3, 1, 1}, Coords{2, 3, 1}, Coords{5, 2, 3}}) {
        Decomposition d(box, dims, minWidth);
        for (int pass = 0; pass < 2; ++pass) {
            // Second pass: non-uniform cuts after balancing on a lopsided distribution.
            if (pass == 1) d.balance(histograms(box, lopsidedPoints(box, 5000, 3), 200));
            int misses = 0;
            for (const auto& x : uniformPoints(box, 3000, 7 + std::uint32_t(pass))) {
                const Coords c = d.owner(x);
                bool ok = true;
                for (int a = 0; a < 3; ++a)
                    ok = ok && c[std::size_t(a)] >= 0 && c[std::size_t(a)] < dims[std::size_t(a)];
                ok = ok && inside(d.subdomain(c), x);
                if (!ok) {
                    ++misses;
                    UNSCOPED_INFO("point " << x.transpose() << " given to " << c[0] << "," << c[1] << "," << c[2]);
                }
            }
            INFO("dims " << dims[0] << "x" << dims[1] << "x" << dims[2] << ", pass " << pass << ": " << misses
                         << " of 3000 points outside the subdomain owner() names");
            CHECK(misses == 0);
        }
        // A point exactly on an interior plane belongs to the subdomain above it.
        for (int a = 0; a < 3; ++a)
            for (int k = 1; k < dims[std::size_t(a)]; ++k) {
                Eigen::Vector3d x = 0.5 * (box.lo + box.hi);
                x[a] = d.cuts(a)[std::size_t(k)];
                CHECK(d.owner(x)[std::size_t(a)] == k);
            }
    }
}

TEST_CASE("owner() wraps positions outside a periodic box", "[parallel][decomposition]") {
    const auto box = makeBox({-4.0, 1.0, 2.0}, {30.0, 24.0, 18.0}, {true, true, true});
    Decomposition d(box, {3, 2, 2}, 2.5);
    d.balance(histograms(box, lopsidedPoints(box, 4000, 21), 200));
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> shift(-3, 3);
    const Eigen::Vector3d L = box.size();
    for (const auto& x : uniformPoints(box, 2000, 17)) {
        Eigen::Vector3i k(shift(rng), shift(rng), shift(rng));
        if (k.isZero()) k[0] = 2;
        const Eigen::Vector3d image = x + k.cast<double>().cwiseProduct(L);
        const Coords expected = d.owner(x);
        const Coords got = d.owner(image);
        INFO("point " << x.transpose() << " shifted by " << k.transpose() << " box lengths");
        CHECK(got == expected);
        CHECK(inside(d.subdomain(got), x));
    }
}

TEST_CASE("owner() gives positions outside a closed box to the nearest subdomain", "[parallel][decomposition]") {
    // Closed along x and z, periodic along y: wrap y by hand, then the nearest subdomain by brute force.
    const auto box = makeBox({-2.0, 0.0, 5.0}, {24.0, 20.0, 15.0}, {false, true, false});
    Decomposition d(box, {4, 2, 3}, 2.5);
    d.balance(histograms(box, lopsidedPoints(box, 4000, 31), 200));
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-1.0, 2.0);  // in units of the box: a third inside per axis
    const Eigen::Vector3d L = box.size();
    int outside = 0;
    for (int i = 0; i < 3000; ++i) {
        const Eigen::Vector3d x = box.lo + Eigen::Vector3d(u(rng), u(rng), u(rng)).cwiseProduct(L);
        Eigen::Vector3d wrapped = x;
        while (wrapped[1] < box.lo[1]) wrapped[1] += L[1];
        while (wrapped[1] >= box.hi[1]) wrapped[1] -= L[1];
        double nearest = std::numeric_limits<double>::infinity();
        for (const auto& c : allCoords(d.dims())) nearest = std::min(nearest, distanceTo(d.subdomain(c), wrapped));
        const Coords c = d.owner(x);
        INFO("point " << x.transpose() << " (wrapped " << wrapped.transpose() << ") given to " << c[0] << "," << c[1]
                      << "," << c[2]);
        CHECK(distanceTo(d.subdomain(c), wrapped) == Approx(nearest).margin(1e-12));
        CHECK(inside(d.subdomain(c), wrapped) == inside(box, wrapped));
        // Beyond a closed face: the end subdomain of that axis.
        for (int a : {0, 2}) {
            if (x[a] < box.lo[a]) CHECK(c[std::size_t(a)] == 0);
            if (x[a] >= box.hi[a]) CHECK(c[std::size_t(a)] == d.dims()[std::size_t(a)] - 1);
        }
        outside += !inside(box, wrapped);
    }
    INFO(outside << " of 3000 points outside the box");
    CHECK(outside > 2000);  // the test exercised the clamping, not only interior points
}

TEST_CASE("rankOf and coordsOf round trip in MPI_Cart_create's z-fastest order", "[parallel][decomposition]") {
    for (const Coords dims : {Coords{1, 1, 1}, Coords{3, 1, 1}, Coords{5, 1, 1}, Coords{2, 3, 1}, Coords{7, 2, 1},
                              Coords{1, 1, 5}, Coords{2, 3, 5}, Coords{3, 7, 2}}) {
        INFO("dims " << dims[0] << "x" << dims[1] << "x" << dims[2]);
        const int n = dims[0] * dims[1] * dims[2];
        // Nested loops with z innermost count the ranks in order.
        int expected = 0;
        for (int i = 0; i < dims[0]; ++i)
            for (int j = 0; j < dims[1]; ++j)
                for (int k = 0; k < dims[2]; ++k, ++expected) {
                    const Coords c{i, j, k};
                    CHECK(rankOf(c, dims) == expected);
                    CHECK(rankOf(c, dims) == (c[0] * dims[1] + c[1]) * dims[2] + c[2]);
                    CHECK(coordsOf(expected, dims) == c);
                }
        REQUIRE(expected == n);
        std::set<Coords> seen;
        for (int r = 0; r < n; ++r) {
            const Coords c = coordsOf(r, dims);
            for (int a = 0; a < 3; ++a) {
                CHECK(c[std::size_t(a)] >= 0);
                CHECK(c[std::size_t(a)] < dims[std::size_t(a)]);
            }
            CHECK(rankOf(c, dims) == r);
            seen.insert(c);
        }
        CHECK(seen.size() == std::size_t(n));
    }
}

TEST_CASE("A box narrower than ranks * minWidth is refused, naming the axis", "[parallel][decomposition]") {
    const auto box = makeBox({0, 0, 0}, {10.0, 12.0, 7.0}, {true, true, true});
    const double minWidth = 2.5;  // room for 4 ranks along x, 4 along y, 2 along z
    CHECK_THROWS_AS(Decomposition(box, {5, 1, 1}, minWidth), std::invalid_argument);
    CHECK_THROWS_WITH(Decomposition(box, {5, 1, 1}, minWidth), Catch::Contains("along x"));
    CHECK_THROWS_AS(Decomposition(box, {1, 5, 1}, minWidth), std::invalid_argument);
    CHECK_THROWS_WITH(Decomposition(box, {1, 5, 1}, minWidth), Catch::Contains("along y"));
    CHECK_THROWS_AS(Decomposition(box, {1, 1, 3}, minWidth), std::invalid_argument);
    CHECK_THROWS_WITH(Decomposition(box, {1, 1, 3}, minWidth), Catch::Contains("along z"));
    CHECK_THROWS_WITH(Decomposition(box, {2, 5, 1}, minWidth), Catch::Contains("along y"));
    CHECK_THROWS_AS(Decomposition(box, {1, 0, 1}, minWidth), std::invalid_argument);
    CHECK_THROWS_WITH(Decomposition(box, {1, 0, 1}, minWidth), Catch::Contains("y needs at least one rank"));
    // Exactly ranks * minWidth wide fits; one rank needs no minimum width.
    CHECK_NOTHROW(Decomposition(box, {4, 4, 2}, minWidth));
    CHECK_NOTHROW(Decomposition(box, {1, 1, 1}, 20.0));
}

TEST_CASE("balance() evens out a lopsided particle distribution", "[parallel][decomposition]") {
    // The dense fifth of x is 20 wide: room for 7 ranks at the quantiles (about 3.2 apart) with
    // minWidth 2.5 to spare, so minWidth does not limit the balance here.
    const auto box = makeBox({-6.0, 3.0, 0.0}, {100.0, 30.0, 24.0}, {true, true, false});
    const double minWidth = 2.5;
    const auto pts = lopsidedPoints(box, 40000, 2024);
    const auto hist = histograms(box, pts, 200);
    for (const Coords dims : {Coords{4, 1, 1}, Coords{5, 1, 1}, Coords{4, 2, 2}, Coords{3, 2, 3}, Coords{7, 2, 1}}) {
        Decomposition d(box, dims, minWidth);
        const double before = Decomposition::imbalance(countsPerRank(d, pts));
        d.balance(hist);
        const auto counts = countsPerRank(d, pts);
        const double after = Decomposition::imbalance(counts);
        INFO("dims " << dims[0] << "x" << dims[1] << "x" << dims[2] << ": imbalance " << before
                     << " with uniform cuts, " << after << " balanced");
        CHECK(before > 2.0);
        CHECK(after < 1.15);
        double total = 0;
        for (double c : counts) total += c;
        CHECK(total == double(pts.size()));  // every particle owned by exactly one rank
        checkCuts(d, minWidth);
        // Each x slab holds about 1/n of the particles (the quantiles the cuts were moved to).
        const int n = dims[0];
        std::vector<double> slab(std::size_t(n), 0.0);
        for (const auto& x : pts) slab[std::size_t(d.owner(x)[0])] += 1;
        for (int k = 0; k < n; ++k) {
            INFO("x slab " << k << " holds " << slab[std::size_t(k)]);
            CHECK(slab[std::size_t(k)] / double(pts.size()) == Approx(1.0 / n).margin(0.01));
        }
    }
}

TEST_CASE("balance() leaves axes with one rank or no histogram at uniform cuts", "[parallel][decomposition]") {
    const auto box = makeBox({0, 0, 0}, {40.0, 30.0, 20.0}, {false, false, false});
    const auto pts = lopsidedPoints(box, 5000, 77);
    auto hist = histograms(box, pts, 100);
    hist[2].clear();  // no histogram along z
    Decomposition d(box, {1, 3, 4}, 2.0);
    const auto zBefore = d.cuts(2);
    d.balance(hist);
    CHECK(d.cuts(0) == std::vector<double>{box.lo[0], box.hi[0]});
    CHECK(d.cuts(2) == zBefore);
    checkCuts(d, 2.0);
}

TEST_CASE("balance() keeps subdomains minWidth wide when the quantiles crowd together", "[parallel][decomposition]") {
    const auto box = makeBox({-5.0, 0.0, 0.0}, {20.0, 20.0, 20.0}, {true, false, false});
    const double minWidth = 3.0;
    const int n = 4;
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0, 1);
    // All particles in a sliver 0.5 wide (narrower than minWidth) at the low end, the middle and
    // the high end of x.
    for (const double start : {0.0, 9.5, 19.5}) {
        std::vector<Eigen::Vector3d> pts;
        for (int i = 0; i < 4000; ++i)
            pts.push_back(box.lo + Eigen::Vector3d(start + 0.5 * u(rng), 20 * u(rng), 20 * u(rng)));
        Decomposition d(box, {n, 2, 1}, minWidth);
        d.balance(histograms(box, pts, 200));
        const auto& c = d.cuts(0);
        INFO("sliver at x - lo in [" << start << ", " << start + 0.5 << "): cuts " << c[0] << " " << c[1] << " " << c[2]
                                     << " " << c[3] << " " << c[4]);
        checkCuts(d, minWidth);
        if (start == 0.0) {
            // The quantiles all lie below lo + minWidth: the cuts pack minWidth apart from lo.
            for (int k = 1; k < n; ++k) CHECK(c[std::size_t(k)] == Approx(box.lo[0] + k * minWidth));
        } else if (start == 19.5) {
            // The quantiles all lie above hi - minWidth: the cuts pack minWidth apart towards hi.
            for (int k = 1; k < n; ++k) CHECK(c[std::size_t(k)] == Approx(box.hi[0] - (n - k) * minWidth));
        } else {
            // The first cut stays at the lowest quantile, inside the sliver; the rest are pushed up.
            CHECK(c[1] >= box.lo[0] + start);
            CHECK(c[1] <= box.lo[0] + start + 0.5);
            for (int k = 2; k < n; ++k) CHECK(c[std::size_t(k)] == Approx(c[1] + (k - 1) * minWidth));
        }
    }
}

TEST_CASE("imbalance() is the largest count over the mean", "[parallel][decomposition]") {
    CHECK(Decomposition::imbalance({7, 7, 7, 7}) == Approx(1.0));
    CHECK(Decomposition::imbalance({3, 1}) == Approx(1.5));
    CHECK(Decomposition::imbalance({0, 0, 0}) == Approx(1.0));  // nothing to balance
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> count(0, 1000);
    for (int trial = 0; trial < 20; ++trial) {
        std::vector<double> counts(std::size_t(1 + trial));
        for (auto& c : counts) c = count(rng);
        double sum = 0;
        for (double c : counts) sum += c;
        if (sum == 0) continue;
        const double expected = *std::max_element(counts.begin(), counts.end()) / (sum / double(counts.size()));
        CHECK(Decomposition::imbalance(counts) == Approx(expected));
        CHECK(Decomposition::imbalance(counts) >= 1.0);
    }
}
