#pragma once
// Virtual material tests on a settled bag (docs/physics.md §8.4, scripts/bench/material.sh): the
// sphere pressed into a block held at its base (indentation, against Hertz), and a cylinder
// between two frictionless plates (uniaxial compression: apparent Young's modulus and Poisson
// ratio). The plates and the base are particles held between steps: a held particle keeps its
// position (a plate's particles their height only) and carries no velocity; the force the rest
// exerts on them is the plate's load.
#include "core/Run.hpp"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace bop::app {

// How a load step is relaxed: steps until the load changes by less than `tolerance` (relative)
// over `window` steps, at least `minSteps`, at most `maxSteps`.
struct Relaxation {
    long long window = 200, minSteps = 1000, maxSteps = 20000;
    double tolerance = 2e-3;
};

struct IndentPoint {
    double depth = 0;  // sphere's travel beyond first contact, simulation length units
    double force = 0;  // the reaction on the sphere along its travel, simulation force units
    long long steps = 0;
};

// The sphere (the model's probe sphere) pressed down (-z) at `xy` into the bag, its base (every
// particle within `baseDepth` of the lowest) held fixed, to each depth of `depths` (length) in
// turn. progress: a line per depth.
std::vector<IndentPoint> indent(core::Run& run, const Eigen::Vector2d& xy, const std::vector<double>& depths,
                                double baseDepth, const Relaxation& relax,
                                const std::function<void(const std::string&)>& progress);

struct CompressPoint {
    double strain = 0;         // the plates' approach over the bag's height
    double stress = 0;         // plate load over the mid-height cross-section, energy / length^3
    double lateralStrain = 0;  // change of the mid-height section's mean radius over the radius
    long long steps = 0;
};

// The bag between plates: its particles within `plateDepth` of its top and bottom held at their
// heights, the top ones moved down by strain x height for each strain of `strains` in turn.
std::vector<CompressPoint> compress(core::Run& run, const std::vector<double>& strains, double plateDepth,
                                    const Relaxation& relax, const std::function<void(const std::string&)>& progress);

}  // namespace bop::app
