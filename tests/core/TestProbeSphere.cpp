// The probe as a rigid sphere (core/ForceField.hpp, docs/physics.md §2.5): a particle inside it is
// pushed out along the line from its centre with the force of a stiff spring on the overlap, the
// force is minus the energy's gradient, and the reaction on the probe is minus their sum.
#include "core/ForceField.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace bop::core;

namespace {

ForceStats pushed(const ProbeSphere& s, const Eigen::Vector3d& centre, Particles& p) {
    for (auto& f : p.force) f.setZero();
    ForceStats stats;
    sphereProbeForces(s, centre, p, stats);
    return stats;
}

}  // namespace

TEST_CASE("the probe sphere pushes a particle out with k (R - d) and has energy k (R - d)^2 / 2", "[core][probe]") {
    const ProbeSphere sphere{2.0, 7.0};  // radius 2 length units, stiffness 7 energy / length^2
    const Eigen::Vector3d centre(1, -2, 0.5);
    Particles p;
    const Eigen::Vector3d at = centre + Eigen::Vector3d(0.6, -0.8, 1.2);  // d = sqrt(2.44) < 2
    p.add(at, 1, 1);
    const ForceStats stats = pushed(sphere, centre, p);
    const double d = (at - centre).norm();
    CHECK(p.force[0].norm() == Approx(7.0 * (2.0 - d)));
    CHECK(p.force[0].normalized().dot((at - centre).normalized()) == Approx(1.0));  // outward
    CHECK(stats.probeEnergy == Approx(0.5 * 7.0 * (2.0 - d) * (2.0 - d)));
    CHECK((stats.probeReaction + p.force[0]).norm() == Approx(0.0).margin(1e-12));
    // The force is minus the energy's gradient (central differences).
    const double h = 1e-6;
    for (int a = 0; a < 3; ++a) {
        Particles q = p;
        q.pos[0][a] += h;
        const double ePlus = pushed(sphere, centre, q).probeEnergy;
        q.pos[0][a] -= 2 * h;
        const double eMinus = pushed(sphere, centre, q).probeEnergy;
        CHECK(-(ePlus - eMinus) / (2 * h) == Approx(p.force[0][a]).epsilon(1e-6));
    }
}

TEST_CASE("the probe sphere leaves particles outside it, and one at its centre, alone", "[core][probe]") {
    const ProbeSphere sphere{1.5, 10.0};
    Particles p;
    p.add(Eigen::Vector3d(1.5001, 0, 0), 2, 1);  // just outside
    p.add(Eigen::Vector3d(0, 0, 0), 2, 2);       // at the centre: no direction to push
    p.add(Eigen::Vector3d(0, 1.0, 0), 2, 3);     // inside, overlap 0.5
    const ForceStats stats = pushed(sphere, Eigen::Vector3d::Zero(), p);
    CHECK(p.force[0].norm() == 0);
    CHECK(p.force[1].norm() == 0);
    CHECK(p.force[2].y() == Approx(5.0));
    CHECK(stats.probeReaction.y() == Approx(-5.0));
}
