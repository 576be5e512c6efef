// Gradient-map force and torque rules: the paper's per-voxel table at voxel centres, a
// continuous field between them, sensible torques, and a spring back from outside the grid.
#include "core/MapField.hpp"
#include "shape/ShapeTestUtil.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace bop;
using namespace bop::core;
using namespace bop::shape;

namespace {

// A slab z in [10, 20) voxels across a 24 x 20 x 30 grid: flat surfaces at z = 10 and z = 19.
GradientMap slab() {
    const Dims d{24, 20, 30};
    return test::mapFrom(test::depthFrom(d, {[](const Eigen::Vector3d& x) { return x.z() >= 10 && x.z() < 20; }}));
}

GradientMap ball() {
    const Dims d{30, 30, 30};
    return test::mapFrom(test::depthFrom(
        d, {[](const Eigen::Vector3d& x) { return (x - Eigen::Vector3d(15.3, 14.8, 15.1)).norm() < 10; }}));
}

}  // namespace

TEST_CASE("GM rules follow the paper's table for a single bag", "[shape][gm]") {
    const GradientMap m = slab();
    const MapField f(m, Interpolation::Trilinear);
    const double h = f.voxelSize();
    CHECK(h == Approx(std::sqrt(3.0) / 2.0));
    const Eigen::Vector3d nz(0, 0, 1);
    auto at = [&](double x, double y, double z) -> Eigen::Vector3d { return Eigen::Vector3d(x, y, z) * h; };
    // Surface particle outside, above the top surface (voxel layer 19): pushed down by d.
    CHECK((f.sample(ParticleKind::Surface, 1, at(5.5, 5.5, 25.5), nz).force - Eigen::Vector3d(0, 0, -6 * h)).norm() <
          1e-12);
    // Surface particle inside the slab, at z = 14.5: pulled to the nearer surface (z = 10.5).
    CHECK((f.sample(ParticleKind::Surface, 1, at(5.5, 5.5, 14.5), nz).force - Eigen::Vector3d(0, 0, -4 * h)).norm() <
          1e-12);
    // Surface particle on the surface layer's centre plane: no force, anywhere along it.
    for (double x : {3.5, 3.9, 4.2, 7.77})
        CHECK(f.sample(ParticleKind::Surface, 1, at(x, 6.3, 19.5), nz).force.norm() < 1e-12);
    // Slightly off the layer: a restoring force back toward it (stiffness about 2 per voxel).
    const Eigen::Vector3d up = f.sample(ParticleKind::Surface, 1, at(4.2, 6.3, 19.7), nz).force;
    CHECK(up.z() < 0);
    CHECK(up.z() == Approx(-(2 * 0.2 - 0.04) * h));
    // The default (mixed) keeps the paper's spring to the voxel centre for surface particles.
    const MapField paper(m);
    CHECK((paper.sample(ParticleKind::Surface, 1, at(4.2, 6.3, 19.7), nz).force - Eigen::Vector3d(0.3, 0.2, -0.2) * h)
              .norm() < 1e-12);
    // Volume particles: free inside, pushed in from outside, pushed one voxel inward on the surface.
    CHECK(f.sample(ParticleKind::Volume, 2, at(5.5, 5.5, 15.5), nz).force.norm() < 1e-12);
    CHECK((f.sample(ParticleKind::Volume, 2, at(5.5, 5.5, 2.5), nz).force - Eigen::Vector3d(0, 0, 8 * h)).norm() <
          1e-12);
    CHECK((f.sample(ParticleKind::Volume, 2, at(12.5, 10.5, 19.5), nz).force - Eigen::Vector3d(0, 0, -h)).norm() <
          1e-6);
}

TEST_CASE("GM torque turns a surface particle's normal toward the surface normal", "[shape][gm]") {
    const GradientMap m = slab();
    const MapField f(m);
    const Eigen::Vector3d p = Eigen::Vector3d(6.5, 6.5, 19.5) * f.voxelSize();
    const Eigen::Vector3d ni = Eigen::Vector3d(1, 0, 0);
    const Eigen::Vector3d tau = f.sample(ParticleKind::Surface, 1, p, ni).torque;
    CHECK((tau - Eigen::Vector3d(0, -1, 0)).norm() < 1e-3);  // x cross z
    CHECK(tau.cross(ni).z() > 0.99);                         // dn/dt = omega x n points along +z
    CHECK(f.sample(ParticleKind::Surface, 1, p, Eigen::Vector3d(0, 0, 1)).torque.norm() < 1e-3);
    CHECK(f.sample(ParticleKind::Volume, 2, p, ni).torque.norm() == 0.0);
}

TEST_CASE("GM field equals the per-voxel rule at centres and is continuous between them", "[shape][gm]") {
    const GradientMap m = ball();
    const MapField tri(m, Interpolation::Trilinear), near(m, Interpolation::Nearest);
    const double h = tri.voxelSize();
    const Dims& d = m.dims();
    for (int species : {1, 2}) {
        const auto kind = species == 1 ? ParticleKind::Surface : ParticleKind::Volume;
        const Eigen::Vector3d n(0, 0, 1);
        std::size_t mismatches = 0;
        for (std::size_t v = 0; v < d.count(); v += 7) {
            const Eigen::Vector3d c = d.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
            const Eigen::Vector3d rule = tri.ruleAtVoxel(v, kind, species, c) * h;
            mismatches += (tri.sample(kind, species, c * h, n).force - rule).norm() > 1e-9;
            mismatches += (near.sample(kind, species, c * h, n).force - rule).norm() > 1e-9;
        }
        CHECK(mismatches == 0);
        // Walk random segments in tiny steps: the trilinear field never jumps; the nearest rule does.
        std::mt19937 rng(species);
        std::uniform_real_distribution<double> u(1.0, 29.0);
        double maxTri = 0, maxNear = 0;
        const double step = 1e-3;
        for (int s = 0; s < 40; ++s) {
            const Eigen::Vector3d a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
            const Eigen::Vector3d dir = (b - a).normalized();
            Eigen::Vector3d prevT = tri.sample(kind, species, a * h, n).force,
                            prevN = near.sample(kind, species, a * h, n).force;
            for (double t = step; t < (b - a).norm(); t += step) {
                const Eigen::Vector3d p = (a + t * dir) * h;
                const Eigen::Vector3d ft = tri.sample(kind, species, p, n).force,
                                      fn = near.sample(kind, species, p, n).force;
                maxTri = std::max(maxTri, (ft - prevT).norm() / h);
                maxNear = std::max(maxNear, (fn - prevN).norm() / h);
                prevT = ft;
                prevN = fn;
            }
        }
        INFO("species " << species << ": largest change per 0.001-voxel step: trilinear " << maxTri << ", nearest "
                        << maxNear);
        CHECK(maxTri < 0.05);  // Lipschitz: at most ~ (|d| + 2) per voxel times the step
        CHECK(maxNear > 0.5);  // the paper's piecewise rule jumps at voxel faces
    }
}

TEST_CASE("a particle beyond the grid is pulled back", "[shape][gm]") {
    const GradientMap m = ball();
    const MapField f(m);
    const double h = f.voxelSize();
    const Eigen::Vector3d far = Eigen::Vector3d(-5, 15, 15) * h;
    const Eigen::Vector3d force = f.sample(ParticleKind::Volume, 2, far, Eigen::Vector3d::UnitZ()).force;
    CHECK(force.x() > 5 * h);  // at least the spring back to the grid edge
}

TEST_CASE("trilinear samples blend the 8 voxels' rules, and carry the voxel's co-planar weight", "[shape][gm]") {
    const GradientMap m = ball();
    const Dims& d = m.dims();
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> inside(1.0, 29.0), anywhere(-4.0, 34.0);
    for (const Interpolation interp : {Interpolation::Mixed, Interpolation::Trilinear, Interpolation::Nearest}) {
        const MapField f(m, interp);
        const double h = f.voxelSize();
        std::size_t blendMismatches = 0, weightMismatches = 0, homeVolume = 0, weightsBelowOne = 0;
        for (int k = 0; k < 20000; ++k) {
            const Eigen::Vector3d x(inside(rng), inside(rng), inside(rng));  // voxel units, away from the edge
            // By definition: the rules of the voxels around x, trilinear weights from the centres.
            const Eigen::Vector3d s = x - Eigen::Vector3d::Constant(0.5);
            const Eigen::Vector3i base = s.array().floor().cast<int>().matrix();
            const Eigen::Vector3d t = s - base.cast<double>();
            Eigen::Vector3d expected = Eigen::Vector3d::Zero();
            bool home = true;
            for (int c = 0; c < 8; ++c) {
                const Eigen::Vector3i at = base + Eigen::Vector3i(c & 1, (c >> 1) & 1, (c >> 2) & 1);
                const double w =
                    (c & 1 ? t.x() : 1 - t.x()) * (c & 2 ? t.y() : 1 - t.y()) * (c & 4 ? t.z() : 1 - t.z());
                const std::size_t v = d.index(at.x(), at.y(), at.z());
                expected += w * f.ruleAtVoxel(v, ParticleKind::Volume, 2, x);
                home = home && m.occ[v] == 2;
            }
            homeVolume += home;
            if (interp != Interpolation::Nearest)
                blendMismatches += (f.sample(ParticleKind::Volume, 2, x * h, n).force - expected * h).norm() >
                                   1e-12 * (1 + expected.norm());
            // The co-planar weight is that of the nearest surface of the voxel holding the particle
            // (MapForces::curvatureWeight), for any interpolation, on and beyond the grid.
            const Eigen::Vector3d y = k % 2 ? x : Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng));
            const float wanted = m.nearestSurface(m.voxelAt((y).array().floor().cast<int>().matrix())).cpWeight;
            weightMismatches += f.sample(ParticleKind::Surface, 1, y * h, n).cpWeight != wanted;
            weightsBelowOne += wanted < 0.999f;
            CHECK(f.sample(ParticleKind::Volume, 2, y * h, n).cpWeight == 1.0f);
        }
        INFO("interpolation " << int(interp) << ": " << homeVolume << " samples with all 8 voxels volume, "
                              << weightsBelowOne << " weights below 1");
        CHECK(blendMismatches == 0);
        CHECK(weightMismatches == 0);
        CHECK(homeVolume > 1000);       // the fast path for volume particles at home is exercised
        CHECK(homeVolume < 19000);      // and so is the blend near the surface
        CHECK(weightsBelowOne > 1000);  // the weights differ between voxels: a wrong voxel would show
    }
}

TEST_CASE("a surface particle's memo gives the map's own samples as the particle walks and jumps", "[shape][gm]") {
    const GradientMap m = ball();
    std::mt19937 rng(11);
    std::normal_distribution<double> stepVoxels(0.0, 0.15);
    std::uniform_real_distribution<double> anywhere(-3.0, 33.0), unit(0.0, 1.0);
    for (const Interpolation interp : {Interpolation::Mixed, Interpolation::Nearest}) {
        const MapField f(m, interp);
        const double h = f.voxelSize();
        MapField::Memo memo;
        Eigen::Vector3d x(15.5, 15.5, 25.4);  // voxel units, near the ball's top
        std::size_t same = 0, moved = 0, mismatches = 0;
        for (int k = 0; k < 20000; ++k) {
            // Mostly small steps (a sheet's particle), sometimes a jump anywhere, on and off the grid.
            if (unit(rng) < 0.01)
                x = Eigen::Vector3d(anywhere(rng), anywhere(rng), anywhere(rng));
            else
                x += Eigen::Vector3d(stepVoxels(rng), stepVoxels(rng), stepVoxels(rng));
            const Eigen::Vector3d n = Eigen::Vector3d(unit(rng) - 0.5, unit(rng) - 0.5, 1.0).normalized();
            const std::size_t before = memo.voxel;
            const MapSample with = f.sample(ParticleKind::Surface, 1, x * h, n, &memo);
            const MapSample without = f.sample(ParticleKind::Surface, 1, x * h, n);
            (memo.voxel == before ? same : moved) += 1;
            mismatches +=
                with.force != without.force || with.torque != without.torque || with.cpWeight != without.cpWeight;
        }
        INFO("interpolation " << int(interp) << ": memo kept " << same << " times, renewed " << moved);
        CHECK(mismatches == 0);  // to the bit
        CHECK(same > 5000);      // both paths are exercised
        CHECK(moved > 1000);
    }
}
