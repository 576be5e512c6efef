// The exact distance transform against brute force on random shapes (issue: at least 20 shapes
// up to 32^3; distances exactly equal; ties may pick either site).
#include "bop/common/DistanceTransform.hpp"

#include <catch2/catch.hpp>

#include <climits>
#include <random>

using namespace bop;

namespace {

struct Case {
    Dims dims;
    std::vector<std::int32_t> label;  // site label or kNoSite
    std::vector<Eigen::Vector3i> sites;
};

// Random shapes of three kinds: scattered points, random blobs' boundaries, random boxes.
Case randomCase(std::mt19937& rng, int kind) {
    std::uniform_int_distribution<int> size(1, 32);
    Case c;
    c.dims = {size(rng), size(rng), size(rng)};
    c.label.assign(c.dims.count(), kNoSite);
    std::uniform_real_distribution<double> u(0, 1);
    const double density = kind == 0 ? 0.002 + 0.05 * u(rng) : 0;
    Eigen::Vector3d centre(u(rng) * c.dims.nx, u(rng) * c.dims.ny, u(rng) * c.dims.nz);
    const double radius = 2 + u(rng) * 14;
    for (int k = 0; k < c.dims.nz; ++k)
        for (int j = 0; j < c.dims.ny; ++j)
            for (int i = 0; i < c.dims.nx; ++i) {
                bool site = false;
                if (kind == 0) site = u(rng) < density;
                if (kind == 1) {
                    const double r = (Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) - centre).norm();
                    site = std::abs(r - radius) < 0.9 || u(rng) < 0.0005;
                }
                if (kind == 2) site = (i == c.dims.nx / 3 || j == c.dims.ny / 2) && k <= c.dims.nz / 2;
                if (site) {
                    c.label[c.dims.index(i, j, k)] = std::int32_t(c.sites.size());
                    c.sites.emplace_back(i, j, k);
                }
            }
    return c;
}

void checkAgainstBruteForce(const Case& c) {
    std::vector<std::int32_t> feature = c.label, dist2;
    exactDistanceTransform(c.dims, feature, dist2, 1);
    std::size_t wrong = 0;
    for (int k = 0; k < c.dims.nz; ++k)
        for (int j = 0; j < c.dims.ny; ++j)
            for (int i = 0; i < c.dims.nx; ++i) {
                const std::size_t v = c.dims.index(i, j, k);
                int best = INT_MAX;
                for (const auto& s : c.sites) best = std::min(best, (s - Eigen::Vector3i(i, j, k)).squaredNorm());
                if (c.sites.empty()) {
                    wrong += feature[v] != kNoSite || dist2[v] != INT32_MAX;
                    continue;
                }
                const int f = feature[v];
                const bool ok = dist2[v] == best && f >= 0 && std::size_t(f) < c.sites.size() &&
                                (c.sites[std::size_t(f)] - Eigen::Vector3i(i, j, k)).squaredNorm() == best;
                wrong += !ok;
            }
    INFO("grid " << c.dims.nx << "x" << c.dims.ny << "x" << c.dims.nz << ", " << c.sites.size() << " sites");
    CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("exact distance transform equals brute force on random shapes", "[shape][edt]") {
    std::mt19937 rng(20261122);
    for (int n = 0; n < 30; ++n) checkAgainstBruteForce(randomCase(rng, n % 3));
}

TEST_CASE("exact distance transform edge cases", "[shape][edt]") {
    SECTION("no sites leaves every voxel without a feature") {
        Case c;
        c.dims = {5, 4, 3};
        c.label.assign(c.dims.count(), kNoSite);
        checkAgainstBruteForce(c);
    }
    SECTION("a single site in a 32^3 grid") {
        Case c;
        c.dims = {32, 32, 32};
        c.label.assign(c.dims.count(), kNoSite);
        c.label[c.dims.index(31, 0, 17)] = 0;
        c.sites = {{31, 0, 17}};
        checkAgainstBruteForce(c);
    }
    SECTION("every voxel a site") {
        Case c;
        c.dims = {7, 1, 9};
        for (std::size_t v = 0; v < c.dims.count(); ++v) {
            c.label.push_back(std::int32_t(v));
            c.sites.push_back(c.dims.coords(v));
        }
        checkAgainstBruteForce(c);
    }
    SECTION("threads give the same result as one core") {
        std::mt19937 rng(7);
        Case c = randomCase(rng, 1);
        std::vector<std::int32_t> f1 = c.label, f2 = c.label, d1, d2;
        exactDistanceTransform(c.dims, f1, d1, 1);
        exactDistanceTransform(c.dims, f2, d2, 2);
        CHECK(d1 == d2);
    }
}
