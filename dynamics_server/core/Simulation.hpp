#pragma once
// The one step of every run (docs/architecture.md): the model (read-only during a step), this
// process's particles and the ghosts of others', the probe, the construction timeline and the
// commands queued for the next step, advanced by step(). One process runs it with the base
// Exchange (nothing to exchange); each rank of a decomposed run with parallel::MpiExchange, which
// brings the halo plan, migration, balancing and reductions. Keyframes, volumes, commands and
// construction exist once, here. Free of MPI, sockets and files.
#include "BloodPressure.hpp"
#include "Bonds.hpp"
#include "Command.hpp"
#include "Construction.hpp"
#include "Exchange.hpp"
#include "ForceField.hpp"
#include "Integrator.hpp"
#include "Params.hpp"
#include "SoundState.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapEdit.hpp"

#include <functional>
#include <map>
#include <memory>
#include <optional>

namespace bop::core {

struct StepStats {
    long long step = 0;        // steps completed
    double time = 0;           // simulation time
    double kinetic = 0;        // kinetic energy (translation + rotation) of this process's particles
    ForceStats forces;         // energies, virial and probe reaction of the last force evaluation
    ConstructionCounts built;  // births and deaths of the last step (every process's)
    BloodSums blood;           // kinetic sum and count of this process's volume particles after the step
    KeyframeAt keyframe;       // the gradient-map frame(s) of the last force evaluation
    double bloodVolume = 0;    // volume voxels of the map(s) in force, length^3 (eq. 15's V)
    double cavityVolume = 0;   // every voxel of the bags in the map(s) in force, length^3
    double total() const { return kinetic + forces.pairEnergy + forces.probeEnergy; }
};

struct StepTimes {
    PhaseTimes forces;        // neighbour list, pairs, gradient map, probe
    double integrate = 0;     // kicks and drift, s
    double construction = 0;  // births and deaths, s
    double total() const {
        return forces.neighbours + forces.pairs + forces.gradientMap + forces.probe + integrate + construction;
    }
};

// Sums over every process, the same on each (totals()).
struct Totals {
    double particles = 0, kinetic = 0, pairEnergy = 0, probeEnergy = 0, virial = 0, virialVolume = 0;
    double bloodMv2 = 0, bloodCount = 0, wallVirial = 0;  // BloodPressure.hpp, ForceStats::wallVirial
    KeyframeAt keyframe;                                  // the map frame(s) of the last forces
    double bloodVolume = 0, cavityVolume = 0;             // volume voxels and bag voxels in force, length^3
    Eigen::Vector3d probeReaction = Eigen::Vector3d::Zero();
    double total() const { return kinetic + pairEnergy + probeEnergy; }
};

// What the last cut did (CutCommand; over every process).
struct CutReport {
    double mapSeconds = 0;      // this process's map edits (every keyframe's window), s
    std::size_t removed = 0;    // particles in the swept volume, taken out
    std::size_t converted = 0;  // volume particles on a new face, made surface particles
    std::size_t bondsBroken = 0;
    std::size_t bags = 0;  // bags that lost voxels
    bool refused = false;  // the blade would have taken every voxel of every bag: nothing changed
};

// Where a process gets its window of the gradient map: the whole map's grid and r0 (arrays empty)
// and any window of any of its keyframes (bop-server reads them from the cache file). Without one,
// the windows are cut from the model's maps.
struct MapSource {
    GradientMap header;
    std::function<GradientMap(int frame, const bop::VoxelWindow&)> crop;
    int frames = 1;  // keyframes (the model's schedule says when each is in force)
};

struct SimulationOptions {
    std::optional<Construction> construction{};  // timeline and parameters; none: no timeline
    long long firstStep = 0;                     // step number of the initial state
    std::optional<MapSource> map{};              // none: windows of model->map
    std::optional<Params> params{};              // none: Params(species count), the neutral weights
    // Cuts already made (a restart after them, a checkpoint-and-go-on): the maps edited and the
    // bonds broken as they were; the particles are the start's.
    std::vector<CutCommand> cuts{};
    std::vector<std::vector<std::uint64_t>> yields{};  // voxels that yielded (Plasticity.hpp), each check's
    // Particles re-sorted in the neighbour list's cell order at the first list rebuild this
    // many steps after the last sort (Exchange::sortParticles; 0: kept in their order).
    long long sortEverySteps = kSortEverySteps;
    static constexpr long long kSortEverySteps = 100;
};

// The widest reach of ghosts a run needs: the pair terms' list range, or the birth front of
// construction (a decomposition's smallest region), length.
double haloReach(const Model& model, const SimulationOptions& options);

class Simulation {
public:
    // A process of a run over `exchange` (outliving this): the model of the whole scene, `all` the
    // particles of the whole scene (the same on every process; each keeps those it owns).
    // Computes the first forces. Collective.
    Simulation(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options, Exchange& exchange);
    // One process with its own exchange (nothing to exchange), as core::Run starts one.
    explicit Simulation(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options = {});
    ~Simulation();
    Simulation(Simulation&&) noexcept;

    // Commands, construction, kick and drift, exchange, forces, kick. UnsoundState (every process
    // alike) when the step ends in a state not fit to go on from (SoundState.hpp). Collective.
    void step();
    void run(long long steps) {
        for (long long s = 0; s < steps; ++s) step();
    }
    // On rank 0: a command every process applies at the start of the next step
    // (std::invalid_argument if it is refused, std::logic_error on other ranks).
    void submit(const Command& command);
    // Forces again for the current state, with energies. Collective.
    void refreshForces();
    // Steps by the minimiser from here on (Fire.hpp: a placed bag's settling), with the scene's
    // time step as its first or from the state `from`; none: the damped dynamics again, from rest.
    void minimise(std::optional<FireParams> fire, const std::optional<FireState>& from = std::nullopt);
    bool minimising() const { return fire_.has_value(); }
    std::optional<FireState> minimiserState() const { return fire_ ? std::optional(fire_->state()) : std::nullopt; }
    // Compute the LJ pair energy only every n steps (1 = every step, the default); the stats of
    // other steps leave it out. Batch runs set their report period here.
    void setEnergyEvery(long long n) { energyEvery_ = n > 0 ? n : 1; }
    // The next step computes the energies too (a served run's steps that publish a frame). The
    // forces do not depend on it.
    void energiesNextStep() { energiesNext_ = true; }
    bool energiesCurrent() const { return energiesCurrent_; }  // the last forces came with energies

    // The scene's constants (the whole box; the whole maps only where the model holds them), and
    // beside them the map in force: this process's region and its window of the keyframes' maps.
    const Model& model() const { return *model_; }
    const MapInForce& mapInForce() const { return maps_; }
    const Params& params() const { return params_; }  // weights, drags and probe in force
    // On rank 0: the params once the queued commands apply, what the next step runs with.
    const Params& paramsAhead() const { return commands_.empty() ? params_ : queued_; }
    const Particles& particles() const { return p_; }
    Particles& particles() { return p_; }  // between steps (tests)
    const Halo& halo() const { return halo_; }
    ProbeState& probe() { return params_.probe; }  // between steps, set alike on every process
    Construction& construction() { return construction_; }
    const Construction& construction() const { return construction_; }
    const StepStats& stats() const { return stats_; }
    const StepTimes& times() const { return times_; }
    void resetTimes() { times_ = StepTimes{}; }
    void setTimes(const StepTimes& t) { times_ = t; }  // carried over when a run continues from a checkpoint
    const ForceField& forceField() const { return field_; }
    long long stepCount() const { return stats_.step; }
    bool commandsQueued() const { return !commands_.empty(); }   // submitted, not yet applied by a step
    std::size_t rebuilds() const { return rebuilds_; }           // neighbour lists and halos built again
    double exchangeSeconds() const { return exchangeSeconds_; }  // in halo, migration and the rebuild vote
    std::size_t mapBytes() const;  // this process's window of the gradient map (of every keyframe)
    // The cuts applied so far, in order (a checkpoint carries them), and what the last one did.
    const std::vector<CutCommand>& cuts() const { return cuts_; }
    const CutReport& lastCut() const { return lastCut_; }
    std::size_t cutCommands() const { return cutCommands_; }  // cut commands taken, refused ones too
    // The voxels dents took out of their bags (Model::plasticity), each check's in voxel order; a
    // checkpoint carries them too.
    const std::vector<std::vector<std::uint64_t>>& yields() const { return yields_; }
    // The bonds in force: the model's less those a cut broke (null: no bonds).
    const std::shared_ptr<const BondNetwork>& bonds() const { return bondNet_; }
    // Voxel counts of each keyframe's whole map (one entry for a static shape, none without a map).
    const std::vector<MapVolume>& frameVolumes() const { return frameVolumes_; }

    // ---- collective ----
    Totals totals() const;
    bool soundEverywhere() const;  // sound() of every process's particles
    // Every process's `mine` (default: its particles), sorted by id, on every process, forces
    // and torques included.
    Particles gather() const { return gather(p_); }
    Particles gather(const Particles& mine) const;

private:
    Simulation(std::unique_ptr<Exchange> own, Exchange* exchange, std::shared_ptr<const Model> model,
               const Particles& all, SimulationOptions options);
    void construct(std::vector<ConstructionEvent> events);  // SimulationConstruction.cpp
    Eigen::Vector3d defaultSeed(int species) const;         // collective
    void placeMaps();                                       // this region's windows of the map(s); SimulationMaps.cpp
    void applyKeyframe(double time);
    void placeRegion(RegionChange r);  // after the exchange's refresh: a new region's windows, a new list
    void forces(bool energies);
    // Cuts (SimulationCuts.cpp): refused unless the run has a map and the numbers are sound; the
    // maps' edits (returning the bags cut); a window with every patch so far; the whole cut.
    void checkCut(const CutCommand& c) const;
    std::vector<int> editMaps(const CutCommand& c);
    // Every keyframe's window patched by `make` (given a reader of the current map and the
    // window held); the bags that lost voxels.
    using PatchMaker = std::function<bop::MapPatch(const bop::MapWindowReader&, const GradientMap&)>;
    std::vector<int> patchMaps(const PatchMaker& make);
    void checkDents();                                           // SimulationPlasticity.cpp
    void yieldVoxels(const std::vector<std::uint64_t>& voxels);  // whole-map indices, sorted
    bop::GradientMap patched(std::size_t frame, bop::GradientMap window) const;
    void cut(const CutCommand& c);                          // collective
    void restoreCuts(const std::vector<CutCommand>& cuts);  // SimulationOptions::cuts and ::yields
    void restoreYields(const std::vector<std::vector<std::uint64_t>>& yields);
    [[noreturn]] void throwUnsound() const;  // collective: UnsoundState naming what a process found

    std::unique_ptr<Exchange> ownExchange_;  // one process's
    Exchange* ex_;
    std::shared_ptr<const Model> model_;  // the whole scene
    Params params_;                       // what commands change
    MapInForce maps_;                     // this process's region (the exchange moves it), its map windows
    ForceField field_;
    DragFactors drag_;                     // of params_.drag
    std::optional<Fire> fire_;             // the minimiser, while it steps
    std::optional<DragFactors> fireDrag_;  // of params_.drag over the minimiser's last step length
    Particles p_;
    Halo halo_;
    BondForces bonds_;                        // the bonded volume's forces (model_->bonds)
    std::vector<double> theta_, ghostTheta_;  // its particles' dilatations, here and the ghosts'
    Construction construction_;
    StepStats stats_;
    StepTimes times_;
    double range_ = 0;  // neighbour-list range, length
    long long energyEvery_ = 1;
    bool energiesNext_ = false, energiesCurrent_ = false;
    bool forcesStale_ = false;       // a command changed the weights since the last forces
    std::vector<Command> commands_;  // queued on rank 0
    Params queued_;                  // rank 0: params_ with commands_ applied (paramsAhead())
    std::size_t rebuilds_ = 0;
    double exchangeSeconds_ = 0;
    std::optional<MapSource> mapSource_;
    std::vector<CutCommand> cuts_;                     // applied, in order
    std::vector<std::vector<bop::MapPatch>> patches_;  // per keyframe, the cuts' patches in order
    CutReport lastCut_;
    std::size_t cutCommands_ = 0;
    std::vector<std::vector<std::uint64_t>> yields_;
    std::map<std::uint64_t, long long> dentedSince_;  // every process alike: the step each dent's voxel fell in front
    std::vector<std::uint64_t> frontBefore_;          // the voxels in front at the last check, sorted
    bool frontSeen_ = false;                          // a check has looked
    std::shared_ptr<const BondNetwork> bondNet_;      // model_->bonds less the bonds cuts broke
    std::vector<MapVolume> frameVolumes_;             // whole-map counts per keyframe
};

}  // namespace bop::core
