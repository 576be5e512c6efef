#pragma once
// Commands to a running simulation (from the network front, a replay or a script). They are
// queued on rank 0 and applied by every process at the start of the next step (Simulation.hpp),
// so that every rank applies them at the same step.
#include "Potentials.hpp"

#include <Eigen/Core>

namespace bop::core {

struct Command {
    enum class Kind : int {
        Probe = 1,   // probe on/off, position (simulation length units), k0, k1
        Drag = 2,    // drag of one species: beta_v (mass / time), beta_tau (inertia / time)
        Seed = 3,    // a particle of one species at a position (simulation length units)
        Birth = 4,   // births of one species on or off
        Weight = 5,  // one interspecies weight (dimensionless): table, receiving species, other species
    };
    enum class Table : int { Lj = 0, CoNormal = 1, CoPlanar = 2 };
    Kind kind = Kind::Probe;
    ProbeState probe;                                    // Probe
    int species = 1;                                     // Drag, Seed, Birth
    double dragV = 0, dragW = 0;                         // Drag
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // Seed, simulation length units
    bool on = false;                                     // Birth
    Table table = Table::Lj;                             // Weight
    int other = 1;                                       // Weight: the other species (`species` receives the force)
    double value = 0;                                    // Weight
};

}  // namespace bop::core
