// Labels (6-connectivity shells, nested species order) and curvature of voxelised spheres.
#include "ShapeTestUtil.hpp"
#include "core/MapField.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <queue>

using namespace bop;
using namespace bop::core;
using namespace bop::shape;

namespace {

auto sphereAt(Eigen::Vector3d c, double r) {
    return [c, r](const Eigen::Vector3d& x) { return (x - c).norm() <= r; };
}

constexpr int kFace[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

// Number of connected components (6- or 26-connectivity) of the voxels where keep(v) holds.
int components(const Dims& d, int connectivity, const std::function<bool(std::size_t)>& keep) {
    std::vector<char> seen(d.count(), 0);
    int comps = 0;
    for (std::size_t s = 0; s < d.count(); ++s) {
        if (seen[s] || !keep(s)) continue;
        ++comps;
        std::queue<std::size_t> q;
        q.push(s);
        seen[s] = 1;
        while (!q.empty()) {
            const Eigen::Vector3i c = d.coords(q.front());
            q.pop();
            for (int dz = -1; dz <= 1; ++dz)
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int steps = std::abs(dx) + std::abs(dy) + std::abs(dz);
                        if (steps == 0 || (connectivity == 6 && steps > 1)) continue;
                        const int a = c.x() + dx, b = c.y() + dy, e = c.z() + dz;
                        if (!d.contains(a, b, e)) continue;
                        const std::size_t n = d.index(a, b, e);
                        if (!seen[n] && keep(n)) {
                            seen[n] = 1;
                            q.push(n);
                        }
                    }
        }
    }
    return comps;
}

}  // namespace

// The paper's rule marks object voxels with a face on the outside. The shell it makes is
// 6-separating (inside and outside never share a face, so no 6-path crosses it) and it is one
// piece under 26-connectivity; as a staircase it is not 6-connected on its own.
TEST_CASE("a voxelised sphere's surface is a 6-connected shell", "[shape][labels]") {
    for (double r : {3.3, 6.0, 9.7, 15.5}) {
        const int n = int(2 * r) + 6;
        const Dims d{n, n + 1, n + 2};
        const Eigen::Vector3d c(0.5 * n + 0.21, 0.5 * (n + 1) - 0.13, 0.5 * (n + 2) + 0.07);
        const GradientMap m = test::mapFrom(test::depthFrom(d, {sphereAt(c, r)}));
        INFO("radius " << r);
        // The shell separates inside from outside: no inside voxel shares a face with an outside one.
        std::size_t leaks = 0;
        for (std::size_t v = 0; v < d.count(); ++v) {
            if (m.occ[v] != 2) continue;
            const Eigen::Vector3i x = d.coords(v);
            for (const auto& o : kFace) leaks += m.occ[d.index(x.x() + o[0], x.y() + o[1], x.z() + o[2])] == 0;
        }
        CHECK(leaks == 0);
        // Inside and outside are each one 6-connected piece; the shell is one 26-connected piece.
        CHECK(components(d, 26, [&](std::size_t v) { return m.occ[v] == 1; }) == 1);
        CHECK(components(d, 6, [&](std::size_t v) { return m.occ[v] == 2; }) == 1);
        CHECK(components(d, 6, [&](std::size_t v) { return m.occ[v] == 0; }) == 1);
        // Every surface voxel is an object voxel with a face on the outside.
        std::size_t bad = 0;
        for (const auto& sv : m.surface) {
            const Eigen::Vector3i x = d.coords(sv.voxel);
            bool out = false;
            for (const auto& o : kFace) out |= m.occ[d.index(x.x() + o[0], x.y() + o[1], x.z() + o[2])] == 0;
            bad += !out;
        }
        CHECK(bad == 0);
    }
}

TEST_CASE("curvature of voxelised spheres of radius 8 to 32 is within 10% of 1/R", "[shape][curvature]") {
    for (double r : {8.0, 12.0, 16.0, 24.0, 32.0}) {
        const int n = int(2 * r) + 12;
        const Dims d{n, n, n};
        const Eigen::Vector3d c = Eigen::Vector3d::Constant(0.5 * n + 0.3);
        const GradientMap m = test::mapFrom(test::depthFrom(d, {sphereAt(c, r)}), 2.0, 2.0);
        std::vector<double> h, kappa, normalErr;
        for (const auto& sv : m.surface) {
            h.push_back(sv.meanCurvature);
            kappa.push_back(sv.kappa);
            const Eigen::Vector3d radial =
                (d.coords(sv.voxel).cast<double>() + Eigen::Vector3d::Constant(0.5) - c).normalized();
            normalErr.push_back(std::acos(std::clamp(radial.dot(sv.normal.cast<double>()), -1.0, 1.0)) * 180 / M_PI);
        }
        double meanH = 0;
        for (double x : h) meanH += x;
        meanH /= double(h.size());
        std::sort(kappa.begin(), kappa.end());
        std::sort(normalErr.begin(), normalErr.end());
        INFO("R = " << r << ": mean H*R = " << meanH * r << ", median kappa*R = " << kappa[kappa.size() / 2] * r
                    << ", 95th percentile normal error " << normalErr[normalErr.size() * 95 / 100] << " deg");
        CHECK(meanH * r == Approx(1.0).epsilon(0.10));
        CHECK(kappa[kappa.size() / 2] * r == Approx(1.0).epsilon(0.10));
        CHECK(normalErr[normalErr.size() * 95 / 100] < 5.0);
        // Co-planar weight: w = 1 / (1 + c kappa r0), c = 4, r0 = 2 voxels.
        CHECK(m.surface.front().cpWeight == Approx(1.0 / (1.0 + 4.0 * m.surface.front().kappa * 2.0)));
    }
}

TEST_CASE("nested bags: species are numbered outer to inner and GM forces point home", "[shape][nested]") {
    const int n = 40;
    const Dims d{n, n, n};
    const Eigen::Vector3d c = Eigen::Vector3d::Constant(20.2);
    const double r1 = 15, r2 = 7;
    const GradientMap m = test::mapFrom(test::depthFrom(d, {sphereAt(c, r1), sphereAt(c, r2)}));
    CHECK(m.bagCount == 2);
    // Along rays from the centre outward the occupying species never increases, and every
    // species 4, 3, 2, 1, 0 appears in that order.
    for (const Eigen::Vector3d& dir :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-1, 0.3, 0.2), Eigen::Vector3d(0.5, -0.5, 0.7)}) {
        std::vector<int> seq;
        for (double t = 0; t < 19; t += 0.25) {
            const Eigen::Vector3i v = (c + t * dir.normalized()).array().floor().cast<int>().matrix();
            const int o = m.occ[d.index(v.x(), v.y(), v.z())];
            if (seq.empty() || seq.back() != o) seq.push_back(o);
        }
        CHECK(seq == std::vector<int>{4, 3, 2, 1, 0});
    }
    // Every species in every voxel outside its own region gets a force with the radial sign
    // that moves it toward its region (paper §3.4; docs/physics.md §4.6).
    MapField field(m, Interpolation::Nearest);
    std::size_t tested = 0, wrong = 0;
    for (int species = 1; species <= 4; ++species) {
        const ParticleKind kind = isSurfaceSpecies(species) ? ParticleKind::Surface : ParticleKind::Volume;
        for (std::size_t v = 0; v < d.count(); ++v) {
            if (m.occ[v] == species) continue;
            const Eigen::Vector3d p = d.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
            const double r = (p - c).norm();
            if (r < 1.0) continue;
            // Target radii of each species' region.
            const double lo = species == 1 ? r1 - 1.5 : species == 2 ? r2 : species == 3 ? r2 - 1.5 : 0;
            const double hi = species == 1 ? r1 : species == 2 ? r1 - 0.5 : species == 3 ? r2 : r2 - 0.5;
            const double radial = field.ruleAtVoxel(v, kind, species, p).dot((p - c) / r);
            if (r > hi + 0.5) {
                ++tested;
                wrong += !(radial < 0);
            } else if (r < lo - 0.5) {
                ++tested;
                wrong += !(radial > 0);
            }
        }
    }
    INFO(tested << " off-target (species, voxel) cases");
    CHECK(tested > 50000);
    CHECK(wrong == 0);
}
