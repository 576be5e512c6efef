#pragma once
// What commands change between steps, apart from the scene (Model), which never changes after
// loading: the interspecies weights of the three pair potentials, each species' drags and the
// probe (MuJoCo keeps its model and its options apart alike). This is their only home: the scene
// file gives their first values (app::Scene::params). The births' switches are the construction
// timeline's (Construction), which turns them too.
#include "Command.hpp"
#include "Model.hpp"

#include <vector>

namespace bop::core {

struct Drag {
    double v = 1.0;  // beta_v: translational damping, mass / time (eq. 10)
    double w = 0.3;  // beta_tau: rotational damping, inertia / time (eq. 11)
};

// alpha_ab for one potential: the weight applied to the force (torque) on a particle of species
// a from a particle of species b (paper eqs. 6-8; asymmetric allowed). Index 0 is unused.
struct WeightMatrix {
    int n = 0;              // species count + 1
    std::vector<double> w;  // n x n, row = receiving species
    WeightMatrix() = default;
    WeightMatrix(int species, double fill) : n(species + 1), w(std::size_t(n) * n, fill) {}
    double operator()(int a, int b) const { return w[std::size_t(a) * n + b]; }
    double& operator()(int a, int b) { return w[std::size_t(a) * n + b]; }
};

struct Params {
    WeightMatrix lj, coNormal, coPlanar;  // alpha_ab of each potential, dimensionless
    std::vector<Drag> drag;               // per species number; [0] unused
    ProbeState probe;                     // on or off, position, k0 and k1

    Params() = default;
    // For `species` species: LJ weights 1 between every two, no oriented terms, Drag's drags, the
    // probe off.
    explicit Params(int species);
    int speciesCount() const { return int(drag.size()) - 1; }

    // A probe, drag or weight command (others: std::invalid_argument). std::invalid_argument,
    // naming what it refuses, for a species out of range, a negative or non-finite weight or a
    // negative drag; the params are then as they were.
    void apply(const Command& c);
};

}  // namespace bop::core
