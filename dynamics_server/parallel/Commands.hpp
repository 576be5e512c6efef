#pragma once
// Commands to a running decomposed simulation. They arrive at rank 0 (from the network front,
// or a batch script), which broadcasts them at the start of the next step, so that every rank
// applies them at the same step. No MPI here: the wire form is a flat array of doubles.
#include "core/ForceField.hpp"

#include <vector>

namespace bop::parallel {

struct Command {
    enum class Kind : int {
        Probe = 1,  // probe on/off, position (simulation length units), k0, k1
        Drag = 2,   // drag of one species: beta_v (mass / time), beta_tau (inertia / time)
        Seed = 3,   // a particle of one species at a position (simulation length units)
        Birth = 4,  // births of one species on or off
        Weight = 5, // one interspecies weight (dimensionless): table, receiving species, other species
    };
    enum class Table : int { Lj = 0, CoNormal = 1, CoPlanar = 2 };
    Kind kind = Kind::Probe;
    core::ProbeState probe;       // Probe
    int species = 1;              // Drag, Seed, Birth
    double dragV = 0, dragW = 0;  // Drag
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // Seed, simulation length units
    bool on = false;              // Birth
    Table table = Table::Lj;      // Weight
    int other = 1;                // Weight: the other species (`species` receives the force)
    double value = 0;             // Weight
};

// Flat form: per command [kind, then its fields]; decode() throws std::invalid_argument naming
// what is wrong with a malformed array.
void encode(const Command& c, std::vector<double>& out);
std::vector<Command> decode(const std::vector<double>& in);

}  // namespace bop::parallel
