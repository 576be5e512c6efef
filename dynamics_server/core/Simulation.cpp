#include "Simulation.hpp"

#include "ParticleRecords.hpp"
#include "Stopwatch.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::core {

double haloReach(const Model& model, const SimulationOptions& o) {
    const double front = o.construction ? o.construction->params().frontR0 : ConstructionParams{}.frontR0;
    return std::max(PairForces::listRange(model, o.params ? *o.params : Params(model.speciesCount())),
                    model.map || o.map ? front * kR0 : 0.0);
}

namespace {

Params paramsFor(const Model& model, std::optional<Params> given) {
    if (!given) return Params(model.speciesCount());
    if (given->speciesCount() != model.speciesCount() || given->lj.n != model.speciesCount() + 1 ||
        given->coNormal.n != given->lj.n || given->coPlanar.n != given->lj.n)
        throw std::invalid_argument("simulation: params for " + std::to_string(given->speciesCount()) +
                                    " species, the model has " + std::to_string(model.speciesCount()));
    return std::move(*given);
}

}  // namespace

Simulation::Simulation(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options,
                       Exchange& exchange)
    : Simulation(nullptr, &exchange, std::move(model), all, std::move(options)) {}

Simulation::Simulation(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options)
    : Simulation(std::make_unique<Exchange>(), nullptr, std::move(model), all, std::move(options)) {}

Simulation::Simulation(std::unique_ptr<Exchange> own, Exchange* exchange, std::shared_ptr<const Model> model,
                       const Particles& all, SimulationOptions options)
    : ownExchange_(std::move(own)),
      ex_(exchange ? exchange : ownExchange_.get()),
      model_(std::move(model)),
      params_(paramsFor(*model_, std::move(options.params))),
      // The map's curvature weights serve the pair terms where the run has a map.
      field_(*model_, params_, model_->map != nullptr || options.map.has_value()),
      drag_(*model_, params_),
      construction_(options.construction ? *options.construction : Construction({}, {}, model_->speciesCount())),
      mapSource_(std::move(options.map)),
      bondNet_(model_->bonds) {
    stats_.step = options.firstStep;
    stats_.time = double(options.firstStep) * model_->integration.dt;
    range_ = field_.pairs().listRange();
    maps_.region = ex_->region(model_->box);
    placeMaps();
    restoreCuts(options.cuts);
    restoreYields(options.yields);
    applyKeyframe(stats_.time);
    // Every process holds `all`: new ids count on from its largest alike.
    if (all.size()) construction_.reserveIds(*std::max_element(all.id.begin(), all.id.end()));
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (!ex_->owns(all.pos[i])) continue;
        const std::size_t k = p_.add(all.pos[i], all.species[i], all.id[i], all.q[i]);
        p_.q[k] = all.q[i];
        p_.normal[k] = all.normal[i];
        p_.vel[k] = all.vel[i];
        p_.omega[k] = all.omega[i];
    }
    // The particles in the order of the LJ list's cells: its box (extended by the ghosts' reach
    // where it holds images or ghosts) and its cell width.
    Box cells = model_->box;
    for (int a = 0; a < 3; ++a)
        if (cells.periodic[std::size_t(a)] || ex_->size() > 1) cells.lo[a] -= range_, cells.hi[a] += range_;
    ex_->sortParticles(cells, field_.pairs().cellWidth(), options.sortEverySteps);
    placeRegion(ex_->start(p_, halo_, range_));
    forces(true);
    stats_.kinetic = kineticEnergy(*model_, p_);
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;

void Simulation::submit(const Command& command) {
    if (ex_->rank() != 0) throw std::logic_error("commands are submitted on rank 0");
    Params next = paramsAhead();
    const bool weight = std::holds_alternative<WeightCommand>(command);
    if (weight || std::holds_alternative<ProbeCommand>(command) || std::holds_alternative<DragCommand>(command))
        next.apply(command);  // refused here, before any process sees it
    // Only weights can switch the oriented terms on or off (one PairForces built to tell).
    if (weight && PairForces::listRange(*model_, next) != range_)
        throw std::invalid_argument(
            "weight command: it would change the interaction range (oriented terms on or "
            "off); give the scene a nonzero weight of that kind to start with");
    if (const auto* c = std::get_if<CutCommand>(&command)) checkCut(*c);
    commands_.push_back(command);
    queued_ = std::move(next);
}

void Simulation::forces(bool energies) {
    const Halo* halo = ex_->hasGhosts() ? &halo_ : nullptr;
    field_.compute(*model_, maps_, params_.probe, p_, stats_.forces, &times_.forces, energies, halo);
    if (bondNet_) {  // the ghosts' dilatations from their owners, then the bonds' forces
        const auto t0 = PhaseClock::now();
        bonds_.dilatation(*bondNet_, p_, halo, theta_);
        ex_->shareGhostValues(theta_, ghostTheta_);
        stats_.forces.pairEnergy += bonds_.add(*bondNet_, p_, halo, theta_, ghostTheta_, stats_.forces.virial);
        times_.forces.pairs += secondsSince(t0);
    }
    forcesStale_ = false;
    energiesCurrent_ = energies;
}

void Simulation::refreshForces() {
    forces(true);
}

void Simulation::placeRegion(RegionChange r) {
    if (r == RegionChange::Kept) return;
    if (r == RegionChange::Moved) {
        maps_.region = ex_->region(model_->box);
        placeMaps();
    }
    field_.requestRebuild();
}

void Simulation::step() {
    auto t0 = PhaseClock::now();
    // Rank 0's commands, the same on every process; seeds join the timeline's events, so that
    // construction places them as a single process does.
    ex_->broadcast(commands_);
    std::vector<ConstructionEvent> events = construction_.eventsAt(stats_.step);
    for (const Command& command : commands_) {
        if (const auto* c = std::get_if<SeedCommand>(&command)) {
            if (c->species < 1 || c->species > model_->speciesCount())
                throw std::invalid_argument("seed command: no species " + std::to_string(c->species));
            ConstructionEvent e;
            e.step = stats_.step;
            e.species = c->species;
            e.positionVoxels = c->position / (maps_.map() ? voxelLength(maps_.map()->r0Voxels) : 1.0);
            events.push_back(e);
        } else if (const auto* b = std::get_if<BirthCommand>(&command)) {
            if (b->species < 1 || b->species > model_->speciesCount())
                throw std::invalid_argument("birth command: no species " + std::to_string(b->species));
            construction_.setBirth(b->species, b->on);
        } else if (const auto* c = std::get_if<CutCommand>(&command)) {
            cut(*c);
        } else {  // a probe, drag or weight command: what the params hold
            params_.apply(command);
            if (std::holds_alternative<WeightCommand>(command)) field_.setParams(*model_, params_), forcesStale_ = true;
            if (std::holds_alternative<DragCommand>(command)) drag_ = DragFactors(*model_, params_), fireDrag_.reset();
        }
    }
    commands_.clear();
    applyKeyframe(double(stats_.step + 1) * model_->integration.dt);  // the time of this step's forces
    checkDents();
    construct(std::move(events));
    times_.construction += secondsSince(t0);
    if (forcesStale_) forces(true);  // the step starts from forces of today's weights and particles

    t0 = PhaseClock::now();
    std::optional<FireKick> kick;
    if (fire_) {  // the minimiser's decision, from every process's sums
        kick = fire_->next(sumInOrder(ex_->allGather(std::vector{firePower(*model_, p_)})));
        if (!fireDrag_ || fireDrag_->dt != kick->dt) fireDrag_ = DragFactors(*model_, params_, kick->dt);
    }
    const DragFactors& drag = kick ? *fireDrag_ : drag_;
    kickDrift(*model_, maps_.region, drag, p_, ex_->wrapsEveryDrift(), kick ? &*kick : nullptr);
    times_.integrate += secondsSince(t0);
    const bool holds = field_.listHolds(maps_.region, p_);
    t0 = PhaseClock::now();
    const RegionChange r = ex_->afterDrift(p_, halo_, range_, holds);
    if (r != RegionChange::Kept) ++rebuilds_;
    placeRegion(r);
    exchangeSeconds_ += secondsSince(t0);
    ++stats_.step;
    stats_.time += model_->integration.dt;
    forces(energiesNext_ || stats_.step % energyEvery_ == 0);
    energiesNext_ = false;
    t0 = PhaseClock::now();
    const KickSums k = kickAndSum(*model_, drag, p_);  // one pass: kinetic, blood and soundness sums
    stats_.kinetic = k.kinetic;
    stats_.blood = {k.volumeMv2, k.volumeCount};
    times_.integrate += secondsSince(t0);
    if (!ex_->allTrue(soundSum(stats_.forces.probeReaction, k.soundTerms))) throwUnsound();
}

void Simulation::minimise(std::optional<FireParams> fire, const std::optional<FireState>& from) {
    if (fire) {
        fire_.emplace(*fire, model_->integration.dt, from);
        return;
    }
    fire_.reset();
    fireDrag_.reset();
    for (std::size_t i = 0; i < p_.size(); ++i) p_.vel[i].setZero(), p_.omega[i].setZero();
    stats_.kinetic = 0;
}

bool Simulation::soundEverywhere() const {
    return ex_->allTrue(sound(*model_, p_, stats_.forces.probeReaction));
}

void Simulation::throwUnsound() const {
    // What each process found, so that every one throws the same words: the first finding.
    const std::vector<Unsoundness> all =
        ex_->allGather(std::vector{findUnsound(*model_, p_, stats_.forces.probeReaction)});
    for (std::size_t r = 0; r < all.size(); ++r)
        if (all[r].what != Unsoundness::None)
            throw UnsoundState(stats_.step,
                               all[r].text() + (ex_->size() > 1 ? " (rank " + std::to_string(r) + ")" : ""));
    throw UnsoundState(stats_.step, "on a process that could not say where");
}

namespace {

// A process's share of the run's totals (Totals), summed in rank order.
struct ProcessSums {
    double particles, kinetic, pairEnergy, probeEnergy, virial, virialVolume;
    Eigen::Vector3d probeReaction;
    double bloodMv2, bloodCount, wallVirial;
};

}  // namespace

Totals Simulation::totals() const {
    const ForceStats& f = stats_.forces;
    const BloodSums blood = bloodSums(*model_, p_);
    const ProcessSums mine{double(p_.size()), stats_.kinetic,  f.pairEnergy, f.probeEnergy, f.virial,
                           f.virialVolume,    f.probeReaction, blood.mv2,    blood.count,   f.wallVirial};
    const ProcessSums sum = sumInOrder(ex_->allGather(std::vector{mine}));
    Totals t;
    t.particles = sum.particles;
    t.kinetic = sum.kinetic;
    t.pairEnergy = sum.pairEnergy;
    t.probeEnergy = sum.probeEnergy;
    t.virial = sum.virial;
    t.virialVolume = sum.virialVolume;
    t.probeReaction = sum.probeReaction;
    t.bloodMv2 = sum.bloodMv2;
    t.bloodCount = sum.bloodCount;
    t.wallVirial = sum.wallVirial;
    t.keyframe = stats_.keyframe;
    t.bloodVolume = stats_.bloodVolume;
    t.cavityVolume = stats_.cavityVolume;
    return t;
}

Particles Simulation::gather(const Particles& p) const {
    std::vector<ParticleWithForces> mine;
    mine.reserve(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) mine.push_back(ParticleWithForces::of(p, i));
    std::vector<ParticleWithForces> all = ex_->allGatherV(mine);
    std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.particle.id < b.particle.id; });
    Particles out;
    for (const auto& r : all) r.appendTo(out);
    return out;
}

}  // namespace bop::core
