// The bonded elastic volume (core/Bonds.hpp, docs/physics.md §8.3): on the fcc lattice an affine
// strain stores the energy of an isotropic solid with lambda = mu + B and mu = k / (sqrt 2 r0);
// the forces are minus the energy's gradient; a process that holds some particles as ghosts, with
// their dilatations from their owner, computes the same forces as one that holds them all.
#include "bop/common/Units.hpp"
#include "core/Bonds.hpp"
#include "core/PairForces.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace bop::core;

namespace {

// Bag 1's two species, bonded with spring k and volume modulus B.
Model bondedModel(double k, double bulk) {
    Model m;
    m.species.resize(3);
    m.species[1].kind = ParticleKind::Surface;
    for (int s : {1, 2}) {
        m.species[std::size_t(s)].bondStiffness = k;
        m.species[std::size_t(s)].bondBulk = bulk;
    }
    return m;
}

// An fcc block of n x n x n cubic cells at nearest-neighbour distance r0, volume species, ids from 1.
Particles fccBlock(int n) {
    Particles p;
    const double a = std::sqrt(2.0) * bop::kR0;  // cubic cell edge
    const Eigen::Vector3d basis[4] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    std::uint64_t id = 1;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (const Eigen::Vector3d& b : basis) p.add((Eigen::Vector3d(x, y, z) + b) * a, 2, id++);
    return p;
}

struct Split {
    Particles owned;
    Halo ghosts;
};

// Particles with every coordinate in [lo, hi] are owned, the rest ghosts.
Split splitInterior(const Particles& all, double lo, double hi) {
    Split s;
    for (std::size_t i = 0; i < all.size(); ++i) {
        const Eigen::Vector3d& x = all.pos[i];
        if (x.minCoeff() >= lo && x.maxCoeff() <= hi) {
            s.owned.add(x, all.species[i], all.id[i]);
        } else {
            s.ghosts.pos.push_back(x);
            s.ghosts.normal.push_back(Eigen::Vector3d::UnitZ());
            s.ghosts.species.push_back(all.species[i]);
            s.ghosts.id.push_back(all.id[i]);
        }
    }
    return s;
}

double energyOf(const BondNetwork& net, Particles& p, const Halo* halo = nullptr) {
    BondForces f;
    std::vector<double> theta, ghostTheta;
    f.dilatation(net, p, halo, theta);
    if (halo) ghostTheta.assign(halo->size(), 0.0);
    for (auto& x : p.force) x.setZero();
    double virial = 0;
    return f.add(net, p, halo, theta, ghostTheta, virial);
}

}  // namespace

TEST_CASE("an affine strain of the bonded fcc lattice stores an isotropic solid's energy", "[core][bonds]") {
    const double k = 2.5, bulk = 1.7;
    const Model model = bondedModel(k, bulk);
    const Particles block = fccBlock(8);
    const BondNetwork net = buildBonds(model, block, 3 * bop::kR0, {});
    // Interior fcc: 12 first and 6 second neighbours each.
    const std::size_t centre = 4 * (8 * 8 * 4 + 8 * 4 + 4) + 1;  // the id of cell (4, 4, 4)'s corner site
    CHECK(net.start[centre + 1] - net.start[centre] == 18);
    const double mu = k / (std::sqrt(2.0) * bop::kR0), lambda = mu + bulk;
    const double volume = bop::kR0 * bop::kR0 * bop::kR0 / std::sqrt(2.0);  // per particle
    const double cell = std::sqrt(2.0) * bop::kR0;
    Eigen::Matrix3d strains[3];
    strains[0] << 1, 0, 0, 0, 0, 0, 0, 0, 0;                     // uniaxial
    strains[1] << 0, 1, 0, 1, 0, 0, 0, 0, 0;                     // shear
    strains[2] << 1, 0.3, -0.2, 0.3, -0.5, 0.4, -0.2, 0.4, 0.8;  // general
    for (Eigen::Matrix3d eps : strains) {
        eps *= 1e-4;
        Particles strained = block;
        for (auto& x : strained.pos) x += eps * x;
        // Energy of the particles whose every bond lies inside the block, per their volume.
        Split s = splitInterior(strained, 2.1 * cell, 5.4 * cell);
        REQUIRE(s.owned.size() > 100);
        const double w = energyOf(net, s.owned, &s.ghosts) / (double(s.owned.size()) * volume);
        const double expected = mu * (eps.array() * eps.array()).sum() + 0.5 * lambda * eps.trace() * eps.trace();
        CHECK(w == Approx(expected).epsilon(0.005));
    }
}

TEST_CASE("bond forces are minus the gradient of the bond energy", "[core][bonds]") {
    const Model model = bondedModel(3.0, 2.0);
    Particles p = fccBlock(2);
    p.species[0] = p.species[5] = 1;  // some sheet particles too: bonds on one side
    const BondNetwork net = buildBonds(model, p, 3 * bop::kR0, {});
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.15, 0.15);
    for (auto& x : p.pos) x += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    energyOf(net, p);
    const std::vector<Eigen::Vector3d> force = p.force;
    const double h = 1e-6;
    for (std::size_t i : {0, 3, 11, 20}) {
        for (int a = 0; a < 3; ++a) {
            Particles q = p;
            q.pos[i][a] += h;
            const double up = energyOf(net, q);
            q.pos[i][a] -= 2 * h;
            const double down = energyOf(net, q);
            CHECK(force[i][a] == Approx(-(up - down) / (2 * h)).margin(1e-6));
        }
    }
}

TEST_CASE("ghosts with their owners' dilatations give the forces of one process", "[core][bonds]") {
    const Model model = bondedModel(2.0, 4.0);
    Particles all = fccBlock(4);
    const BondNetwork net = buildBonds(model, all, 3 * bop::kR0, {});
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (auto& x : all.pos) x += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng));
    energyOf(net, all);  // one process: all its own
    BondForces whole;
    std::vector<double> thetaAll;
    whole.dilatation(net, all, nullptr, thetaAll);
    // This process holds the lower half; the upper half are ghosts whose owner sent their theta.
    const double mid = 2.0 * std::sqrt(2.0) * bop::kR0;
    Split s;
    std::vector<double> ghostTheta;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (all.pos[i].z() < mid) {
            s.owned.add(all.pos[i], all.species[i], all.id[i]);
        } else {
            s.ghosts.pos.push_back(all.pos[i]);
            s.ghosts.normal.push_back(Eigen::Vector3d::UnitZ());
            s.ghosts.species.push_back(all.species[i]);
            s.ghosts.id.push_back(all.id[i]);
            ghostTheta.push_back(thetaAll[i]);
        }
    }
    BondForces part;
    std::vector<double> theta;
    part.dilatation(net, s.owned, &s.ghosts, theta);
    double virial = 0;
    part.add(net, s.owned, &s.ghosts, theta, ghostTheta, virial);
    std::size_t k = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (all.pos[i].z() >= mid) continue;
        CHECK((s.owned.force[k] - all.force[i]).norm() == Approx(0.0).margin(1e-12));
        ++k;
    }
}

TEST_CASE("a bond lets go beyond the cut, and bags side by side are not bonded", "[core][bonds]") {
    Model model = bondedModel(1.0, 0.0);
    model.species.resize(5);
    model.species[3] = model.species[1];
    model.species[4] = model.species[2];
    Particles p;
    p.add(Eigen::Vector3d(0, 0, 0), 2, 1);
    p.add(Eigen::Vector3d(bop::kR0, 0, 0), 2, 2);
    p.add(Eigen::Vector3d(0, bop::kR0, 0), 4, 3);  // bag 2, beside bag 1
    const BondNetwork beside = buildBonds(model, p, 1.6 * bop::kR0, {0, 0, 0});
    CHECK(beside.bonds() == 1);
    const BondNetwork nested = buildBonds(model, p, 1.6 * bop::kR0, {0, 0, 1});  // bag 2 inside bag 1
    CHECK(nested.bonds() == 3);
    p.pos[1].x() = 1.7 * bop::kR0;
    CHECK(energyOf(beside, p) == 0.0);
    p.pos[1].x() = 1.5 * bop::kR0;
    CHECK(energyOf(beside, p) == Approx(0.5 * 0.25 * bop::kR0 * bop::kR0));
}

TEST_CASE("a support anchors the particles placed near the bottom where they were placed", "[core][bonds]") {
    const Model model = bondedModel(2.0, 0.0);
    Particles p;
    p.add(Eigen::Vector3d(0, 0, 1), 2, 1);
    p.add(Eigen::Vector3d(bop::kR0, 0, 1), 2, 2);
    p.add(Eigen::Vector3d(0, 0, 1 + bop::kR0), 2, 3);
    const BondNetwork net = buildBonds(model, p, 3 * bop::kR0, {}, 0.5);
    CHECK(net.anchorStiffness[1] == Approx(kAnchorBonds * 2.0));
    CHECK(net.anchorStiffness[2] == Approx(kAnchorBonds * 2.0));
    CHECK(net.anchorStiffness[3] == 0.0);
    // Particles 1 and 2 moved together along y: their bond unstretched, each anchor pulls back.
    p.pos[0].y() += 0.1;
    p.pos[1].y() += 0.1;
    const double e = energyOf(net, p);
    CHECK(p.force[0].y() == Approx(-kAnchorBonds * 2.0 * 0.1).margin(1e-3));  // the bonds to 3 barely stretch
    CHECK(e == Approx(2 * 0.5 * kAnchorBonds * 2.0 * 0.01).epsilon(0.01));
}
