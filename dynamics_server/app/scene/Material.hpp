#pragma once
// Tissue in physical units (docs/physics.md §8): each bag's material (Young's modulus, Poisson
// ratio, density, relaxation time) becomes the scene's unit system and the bonds (core/Bonds.hpp),
// weights, map stiffnesses and drags that give it. A scene without [[material]] keeps its weights as set by hand (the
// paper's), its lengths in mm and its time and force in simulation units.
#include "bop/common/ConfigTable.hpp"
#include "bop/common/UnitSystem.hpp"
#include "core/Model.hpp"
#include "core/Params.hpp"

#include <string>
#include <vector>

namespace bop::app {

struct Material {
    std::string name;           // shown in reports: the [[material]]'s name, else its first bag's
    double youngKpa = 0;        // Young's modulus, kPa
    double poisson = 0.3;       // Poisson ratio, from 0.25 (the bonds alone) to below 0.5
    double densityKgM3 = 1000;  // mass density, kg/m^3
    double relaxationS = 0.05;  // time in which the drag takes a particle's speed down by e, s
    // The gradient map's spring on each particle as a fraction of a nearest-neighbour bond's: it
    // holds the bag where its map is without stiffening it (docs/physics.md §8.2).
    double shapeHold = kDefaultShapeHold;
    static constexpr double kDefaultShapeHold = 0.005;
};

// What the calibration chose, for every bag and for the report.
struct Calibration {
    UnitSystem units;
    double massScaling = 1;      // the particle mass times this (mass scaling: the dynamics, not the statics)
    std::vector<double> weight;  // per bag: its P-wave modulus over the stiffest one's
    // Per bag: the nearest neighbours' bond k (energy / length^2) and the volume term's B
    // (energy / length^3), core/Bonds.hpp.
    std::vector<double> bond, bulk;
};

// The P-wave modulus lambda + 2 mu of the stiffest material in simulation units: the fastest
// sound, which sets the stable time step, the same in every scene (docs/physics.md §8.1).
inline constexpr double kPWaveModulus = 6.0;
// The sheet's co-normal and co-planar weights at weight 1: they keep its normals and its plane
// smooth, a small part of its stiffness beside the bonds.
inline constexpr double kSheetWeight = 0.05;

// [[material]] tables (docs/scene-format.md): one Material per bag of `bagNames`, in their order;
// none when the scene has no [[material]]. bop::Error naming the key for an unknown bag, a bag given
// twice or left without a material, or a value out of range.
std::vector<Material> readMaterials(const ConfigTable& root, const std::vector<std::string>& bagNames);

// The scene's lengths: mm per simulation length unit for a map of `voxelMm` mm voxels whose r0
// spans `r0Voxels` voxels.
inline double lengthMmOf(double voxelMm, double r0Voxels) {
    return voxelMm * r0Voxels / bop::kR0;
}

// Calibrates `materials` (one per bag, bag k's species 2k-1 and 2k) at `lengthMm`: the unit of
// energy makes the stiffest material's P-wave modulus kPWaveModulus, so the paper's time step stays
// stable whatever the moduli; each bag's bonds give its E and Poisson ratio on the fcc lattice
// (lambda = mu = k / (sqrt 2 r0) from the springs, B = lambda - mu for the rest); time follows from
// the mass of a particle (its fcc cell of the first material's density, times massScaling).
Calibration calibrate(const std::vector<Material>& materials, double lengthMm, double massScaling);

// Writes the calibration into the model's species (bonds, map stiffness) and the params' weights
// (no LJ within a bonded bag, the harmonic mean of the weights across a border) and drags.
void applyCalibration(const Calibration& c, const std::vector<Material>& materials, core::Model& model,
                      core::Params& params);

// The lines a run prints: the units, and per material what it asked and what it was given.
std::vector<std::string> calibrationReport(const Calibration& c, const std::vector<Material>& materials,
                                           double timeStep);

}  // namespace bop::app
