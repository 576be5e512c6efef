#pragma once
// What commands change between steps, apart from the scene (Model), which never changes: the
// interspecies weights of the three pair potentials, each species' drags and the probe (MuJoCo
// keeps its model and its options apart alike). The scene's Model gives their first values. The
// births' switches are the construction timeline's (Construction), which turns them too.
#include "Command.hpp"
#include "Model.hpp"

#include <vector>

namespace bop::core {

struct Drag {
    double v = 1.0;  // beta_v: translational damping, mass / time (eq. 10)
    double w = 0.3;  // beta_tau: rotational damping, inertia / time (eq. 11)
};

struct Params {
    WeightMatrix lj, coNormal, coPlanar;  // alpha_ab of each potential (Model.hpp), dimensionless
    std::vector<Drag> drag;               // per species number; [0] unused
    ProbeState probe;                     // on or off, position, k0 and k1

    Params() = default;
    explicit Params(const Model& scene);  // the scene's weights and drags, the probe off

    // A probe, drag or weight command (others: std::invalid_argument). std::invalid_argument,
    // naming what it refuses, for a species out of range, a negative or non-finite weight or a
    // negative drag; the params are then as they were.
    void apply(const Command& c);
};

}  // namespace bop::core
