#pragma once
// A whole scene for the server: the shape ([grid], [shape]) or a bulk box ([box]), the species
// table, interspecies weights, dynamics parameters, probe, construction timeline and run
// settings. See docs/scene-format.md for every key and its unit.
#include "app/scene/Material.hpp"
#include "app/scene/Placement.hpp"
#include "core/Construction.hpp"
#include "core/Fire.hpp"
#include "core/ForceField.hpp"
#include "core/Model.hpp"
#include "core/Params.hpp"
#include "shape/ShapeSpec.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bop::app {

struct BulkBox {
    Eigen::Vector3d sizeR0{10, 10, 10};  // box edges, multiples of r0
    double spacingR0 = 1.0;              // nearest-neighbour distance of the initial fcc lattice, r0
    double jitterR0 = 0.0;               // random displacement of each lattice site, r0
    int speciesNumber = 1;               // species of the lattice particles
};

struct RunSettings {
    long long steps = 0;               // default for --steps
    long long snapshotEverySteps = 0;  // extended XYZ snapshot period, steps (0 = none)
    long long reportEverySteps = 0;    // progress line period, steps (0 = about 10 per run)
    // A bag built by placement ends its run once settled: the mean kinetic energy per particle,
    // checked every settleEverySteps steps, at or below settleKinetic at every check over
    // settleCalmSteps steps (steps then caps the run; app/runs/SettleWatch.hpp).
    // docs/scene-format.md [construction].
    bool untilSettled = false;
    double settleKinetic = 1e-4;      // energy units (epsilon) per particle
    long long settleEverySteps = 10;  // steps between checks
    long long settleCalmSteps = 50;   // steps the checks must stay calm over
    // The time step of a batch run that ends once settled, simulation time units: the settling
    // wants the minimum, not the trajectory to it (default 1.5 x [dynamics] time_step, at most
    // 0.03, the paper's largest). useSettleTimeStep() puts it in the start's model.
    double settleTimeStep = 0.03;
    // How the bag settles: by the minimiser (core/Fire.hpp, the default) until the rule above
    // holds under it, then by the damped dynamics from rest until it holds again
    // (app/runs/Settling.hpp); none: by the damped dynamics alone.
    std::optional<core::FireParams> settleFire = core::FireParams{};
};

// The ventricle's blood-pressure curve and volumes (paper §5.2; app/CardiacSeries.hpp).
struct PressureSettings {
    long long averageSteps = 10;      // steps per averaged sample (the paper: 10)
    double peakMmHg = 120;            // the fitted curve is scaled to this peak, mmHg
    bool paperEq15 = false;           // the paper's eq. 15 (1/N on the virial) instead of the standard formula
    int skipCycles = 1;               // keyframe cycles left out of the averaged cycle (settling)
    long long volumeEverySteps = 50;  // period of the particle-filled volume measurement, steps
};

struct Scene {
    std::string file;
    std::optional<shape::ShapeSpec> shape;  // the bag(s), or nothing for bulk material
    std::optional<BulkBox> bulk;
    std::shared_ptr<const core::Model> model;  // as parsed: without its map or box (RunStart::model has them)
    core::Params params;                       // the first weights and drags (commands change them); probe: `probe`
    core::ConstructionParams construction;
    std::vector<core::ConstructionEvent> timeline;
    std::optional<PlacementParams> placement;  // method = "place": particles set on the map at the start
    core::ProbeState probe;
    std::optional<Eigen::Vector3d> probePositionVoxels;
    RunSettings run;
    std::optional<PressureSettings> pressure;  // [pressure]: write the pressure curve and volumes
    std::uint64_t seed = 1;
    // Materials (docs/physics.md §8), one per bag or none: with them the model's units are physical
    // (mass, time and force as well as length) and the weights, map stiffnesses and drags are the
    // calibration's.
    std::vector<Material> materials;
    std::optional<Calibration> calibration;
    bool realTime = true;  // [units] real_time: a served run with materials keeps to the wall clock
    // [support] below_mm: the particles placed within this height of the bags' lowest particle
    // are anchored where they were placed (core/Bonds.hpp), mm; none: the map alone holds the bags.
    std::optional<double> supportBelowMm;
};

// Reads and checks every table; bop::Error naming the file and key on any problem.
Scene loadScene(const std::string& path);

// The default species table, weights and drags for a map of `bags` nested bags (paper-like bags).
void defaultSpecies(core::Model& m, core::Params& params, int bags);

// Initial particles of a bulk box: an fcc lattice filling the box (deterministic jitter).
core::Particles bulkLattice(const Scene& scene);

}  // namespace bop::app
