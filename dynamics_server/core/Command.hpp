#pragma once
// Commands to a running simulation (from the network front, a replay or a script), one struct per
// kind. They are queued on rank 0 and applied by every process at the start of the next step
// (Simulation.hpp), so that every rank applies them at the same step; parallel/Commands.hpp
// carries them across ranks as typed records.
#include "Potentials.hpp"

#include <Eigen/Core>

#include <variant>

namespace bop::core {

// The probe on or off, at a position (simulation length units), with k0 and k1 (eq. 9).
struct ProbeCommand {
    ProbeState probe;
};

// The drag of one species: beta_v (mass / time) and beta_tau (inertia / time).
struct DragCommand {
    int species = 1;
    double dragV = 0, dragW = 0;
};

// A particle of one species at a position (simulation length units).
struct SeedCommand {
    int species = 1;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
};

// Births of one species on or off.
struct BirthCommand {
    int species = 1;
    bool on = false;
};

enum class WeightTable : int { Lj = 0, CoNormal = 1, CoPlanar = 2 };

// One interspecies weight (dimensionless) of one table: `species` receives the force from `other`.
struct WeightCommand {
    WeightTable table = WeightTable::Lj;
    int species = 1, other = 1;
    double value = 0;
};

// A blade swept from `from` to `to` (simulation length units; equal for a point) with `radius`
// (length units): every voxel of the gradient map whose centre lies in the volume swept leaves
// its bag, the particles in it leave the run, and the cut faces become surface (SimulationCuts.cpp,
// docs/physics.md §9).
struct CutCommand {
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
    double radius = 0;
};

using Command = std::variant<ProbeCommand, DragCommand, SeedCommand, BirthCommand, WeightCommand, CutCommand>;

}  // namespace bop::core
