#pragma once
// Tissue in physical units (docs/physics.md §8): each bag's material (Young's modulus, Poisson
// ratio, density, relaxation time) becomes the scene's unit system and the weights, map stiffnesses
// and drags that give it. A scene without [[material]] keeps its weights as set by hand (the
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
    double poisson = 0.3;       // Poisson ratio: Hertz's E / (1 - nu^2) (the bag's own: docs/physics.md §8.3)
    double densityKgM3 = 1000;  // mass density, kg/m^3
    double relaxationS = 0.05;  // time in which the drag takes a particle's speed down by e, s
    double shapeHold = 1.0;     // the gradient map's forces as a fraction of the material's weight
};

// What the calibration chose, for every bag and for the report.
struct Calibration {
    UnitSystem units;
    double massScaling = 1;      // the particle mass times this (mass scaling: the dynamics, not the statics)
    double modulusSim = 0;       // a bag's indentation modulus at weight 1 (kBagModulus), energy / length^3
    std::vector<double> weight;  // per bag: its material's modulus over the stiffest one's
};

// [[material]] tables (docs/scene-format.md): one Material per bag of `bagNames`, in their order;
// none when the scene has no [[material]]. bop::Error naming the key for an unknown bag, a bag given
// twice or left without a material, or a value out of range.
std::vector<Material> readMaterials(const ConfigTable& root, const std::vector<std::string>& bagNames);

// The scene's lengths: mm per simulation length unit for a map of `voxelMm` mm voxels whose r0
// spans `r0Voxels` voxels.
inline double lengthMmOf(double voxelMm, double r0Voxels) {
    return voxelMm * r0Voxels / bop::kR0;
}

// The Young's modulus a bag shows to the probe sphere at weight 1 (every weight 1, the map's at
// shape_hold 1, the default LJ switch and oriented weights), energy / length^3, at r0 = r0Voxels
// voxels: Hertz fitted to indentations of a block at r0_voxels 1.4 and 2, measured once by
// scripts/bench/material.sh (docs/physics.md §8.3), linear in between and held beyond.
double bagModulus(double r0Voxels);

// Calibrates `materials` (one per bag, bag k's species 2k-1 and 2k) at `lengthMm` and r0Voxels:
// the unit of energy makes the stiffest material's modulus the bag's at weight 1, so every weight is
// at most 1 and the time step of the paper's range stays stable; time follows from the mass of a
// particle (its fcc cell of the first material's density, times massScaling).
Calibration calibrate(const std::vector<Material>& materials, double lengthMm, double r0Voxels, double massScaling);

// Writes the calibration into the model's species and the params' weights and drags.
void applyCalibration(const Calibration& c, const std::vector<Material>& materials, core::Model& model,
                      core::Params& params);

// The lines a run prints: the units, and per material what it asked and what it was given.
std::vector<std::string> calibrationReport(const Calibration& c, const std::vector<Material>& materials,
                                           double timeStep);

}  // namespace bop::app
