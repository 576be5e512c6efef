#pragma once
// The scene model: what a step reads and what never changes after loading (species table,
// potentials' forms, integration parameters, box, the whole gradient maps). What commands change
// (weights, drags, the probe) is Params.hpp's; the map in force at a step (this process's window,
// the keyframes' blend) is MapInForce.hpp's.
#include "Keyframes.hpp"
#include "Plasticity.hpp"
#include "Potentials.hpp"
#include "bop/common/GradientMap.hpp"
#include "bop/common/SurfaceFilters.hpp"
#include "bop/common/UnitSystem.hpp"
#include "core/MapField.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bop::core {

struct Species {
    std::string name;                               // shown in reports and snapshots (no spaces)
    ParticleKind kind = ParticleKind::Volume;       // surface (oriented) or volume
    std::array<float, 3> colour{0.5f, 0.5f, 0.5f};  // RGB in [0, 1]
    double alphaForceOp = 1.0;                      // alpha_f^OP: weight of LJ + co-normal + co-planar forces (eq. 2)
    double alphaForceGm = 1.0;                      // alpha_f^GM: gradient-map spring stiffness, energy / length^2
    double alphaTorqueOp = 1.0;                     // alpha_tau^OP: weight of oriented-particle torques (eq. 3)
    double alphaTorqueGm = 1.0;                     // alpha_tau^GM: gradient-map torque, energy
    // A bonded elastic volume (Bonds.hpp): the nearest neighbours' spring k, energy / length^2
    // (0: the species is not bonded), and the volume term's modulus B, energy / length^3.
    double bondStiffness = 0;
    double bondBulk = 0;
};

struct Box {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();  // simulation length units
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    std::array<bool, 3> periodic{false, false, false};
    Eigen::Vector3d size() const { return hi - lo; }
    // x moved into [lo, hi) along the periodic axes; the other axes as they are.
    Eigen::Vector3d wrap(Eigen::Vector3d x) const {
        for (int a = 0; a < 3; ++a) {
            if (!periodic[std::size_t(a)]) continue;
            const double L = hi[a] - lo[a];
            x[a] -= L * std::floor((x[a] - lo[a]) / L);
            if (x[a] >= hi[a]) x[a] = lo[a];  // rounding can land on hi, which is lo's image
        }
        return x;
    }
};

struct Integration {
    double dt = 0.02;      // time step, simulation time units (docs/physics.md §3.4: 0.02-0.03)
    double inertia = 0.3;  // moment of inertia of a surface particle, mass * length^2
    double skinR0 = 0.3;   // neighbour-list skin beyond the largest cutoff, multiples of r0
    // Inner skin of the pair loops' pruned copies of the list (PrunedPairs.hpp), multiples of r0;
    // 0, or at least skinR0: the loops read the whole list.
    double pruneR0 = 0.05;
    // The most a particle moves in one step, multiples of r0 (0: no limit); its velocity is
    // scaled down to it after each half kick, as LAMMPS's fix nve/limit does. No sound run comes
    // near it (thermal motion moves about 0.01 r0 a step); it keeps a blow-up (a probe driven
    // hard into the bag, particles shot into each other) from flinging particles away.
    double maxStepR0 = 0.2;
    double maxTurn = 0.5;  // the most a surface particle turns in one step, radians (0: no limit)
    // The LJ loop's pair arithmetic in single precision, its sums in double ([dynamics] precision
    // = "mixed"; LjPairLoop.hpp, docs/dynamics.md "Mixed precision"); else double throughout.
    bool mixedPrecision = false;
};

// The probe as a rigid sphere (docs/physics.md §2.5) instead of eq. 9's LJ particle: a particle
// whose centre lies within `radius` of the probe's is pushed out along the line from the probe,
// force stiffness (radius - d), energy stiffness (radius - d)^2 / 2.
struct ProbeSphere {
    double radius = 0;     // simulation length units
    double stiffness = 0;  // energy / length^2
};

struct BondNetwork;  // Bonds.hpp

struct Model {
    std::vector<Species> species;  // index = species number; [0] is a placeholder
    LjParams ljParams;
    OrientedParams oriented;
    Integration integration;
    Box box;
    bool curvatureWeighting = true;          // multiply co-planar weights by the map's curvature weight
    std::optional<ProbeSphere> probeSphere;  // the probe's form: this sphere, or eq. 9's LJ particle
    // What a simulation unit is in mm, kg and s (docs/physics.md §8): for reports and files only,
    // the physics never reads it.
    UnitSystem units;
    // The whole map of the bag(s), where the model holds it (tests, tools);
    // null for bulk material and for runs that read windows from the map's cache file
    // (SimulationOptions::map). The map in force at a step is Simulation::mapInForce().
    std::shared_ptr<const GradientMap> map;
    // Keyframed shapes (Keyframes.hpp): every frame's whole map, `map` being one of them. Empty or
    // one map: a static shape.
    std::vector<std::shared_ptr<const GradientMap>> frames;
    KeyframeSchedule keyframes;
    // The bonds of the bags whose species have a bond stiffness (Bonds.hpp), built once from the
    // placed particles; null: no bonds.
    std::shared_ptr<const BondNetwork> bonds;
    core::Interpolation interpolation = core::Interpolation::Trilinear;
    // How the map's normals, curvatures and co-planar weights were made (the shape's [grid]): the
    // map edits of a cut (CutCommand) make the cut faces' alike.
    SurfaceGeometryParams mapGeometry;
    PlasticityParams plasticity;  // lasting deformation (Plasticity.hpp); off by default

    int speciesCount() const { return int(species.size()) - 1; }
    bool isSurface(int s) const { return species[std::size_t(s)].kind == ParticleKind::Surface; }
    bool hasSurfaceSpecies() const {
        for (int s = 1; s <= speciesCount(); ++s)
            if (isSurface(s)) return true;
        return false;
    }
};

}  // namespace bop::core
