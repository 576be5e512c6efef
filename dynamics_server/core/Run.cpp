#include "Run.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::core {

ExchangeMaker oneProcess() {
    return [](const Box&, double) { return std::make_unique<Exchange>(); };
}

struct Run::Impl {
    std::shared_ptr<const Model> model;
    SimulationOptions options;  // the start's (its map source serves a reseat too)
    ExchangeMaker exchanges;    // outlives the exchanges it made
    // This process's share: its exchange and the step over it (made again by a reseat).
    std::unique_ptr<Exchange> ex;
    std::unique_ptr<Simulation> sim;
    long long energyEvery = 1;
    std::optional<FireParams>
        fire;  // the minimiser's, while it steps (a reseat carries its state, as a checkpoint does)
    // This process's counters of the simulations a reseat let go (the run's totals go on).
    double carriedMigrations = 0, carriedRebuilds = 0, carriedExchange = 0, carriedRebalances = 0;
    std::optional<SoundSnapshot> sound;  // this process's particles of the last sound state
    Impl(std::shared_ptr<const Model> m, const Particles& all, SimulationOptions o, ExchangeMaker x)
        : model(std::move(m)), options(o), exchanges(std::move(x)) {
        start(all, std::move(o));
        keepIfSound();
    }
    void start(const Particles& all, SimulationOptions o) {  // collective
        sim.reset();                                         // the old run's memory goes first
        ex.reset();
        ex = exchanges(model->box, haloReach(*model, o));
        sim = std::make_unique<Simulation>(model, all, std::move(o), *ex);
    }
    void keepIfSound() {  // collective
        if (sim->soundEverywhere())
            sound = SoundSnapshot{sim->particles(), sim->construction(), sim->stepCount()};
        else
            sound.reset();  // not an older state of another start
    }
};

Run::Run(std::shared_ptr<const Model> model, const Particles& all, SimulationOptions options, ExchangeMaker exchanges)
    : impl_(std::make_unique<Impl>(std::move(model), all, std::move(options), std::move(exchanges))) {}
Run::~Run() = default;

void Run::step() {
    impl_->sim->step();  // sound, or it threw
    const long long n = impl_->sim->stepCount();
    if (n % kSoundSnapshotEvery == 0) {
        if (!impl_->sound) impl_->sound.emplace(SoundSnapshot{{}, impl_->sim->construction(), n});
        // Copied into the last snapshot's arrays: no fresh pages for a 10^6-particle bag each time.
        impl_->sound->particles = impl_->sim->particles();
        impl_->sound->construction = impl_->sim->construction();
        impl_->sound->step = n;
    }
}

std::optional<SoundSnapshot> Run::lastSound() const {
    const auto& s = impl_->sound;
    if (!impl_->ex->allTrue(s.has_value())) return std::nullopt;
    return SoundSnapshot{impl_->sim->gather(s->particles), s->construction, s->step};
}
void Run::refreshForces() {
    impl_->sim->refreshForces();
}
void Run::resetTimes() {
    impl_->sim->resetTimes();
}
void Run::energiesNextStep() {
    impl_->sim->energiesNextStep();
}
bool Run::energiesCurrent() const {
    return impl_->sim->energiesCurrent();
}
void Run::setEnergyEvery(long long n) {
    impl_->energyEvery = n;
    impl_->sim->setEnergyEvery(n);
}
void Run::minimise(std::optional<FireParams> fire, const std::optional<FireState>& from) {
    impl_->fire = fire;
    impl_->sim->minimise(fire, from);
}
bool Run::minimising() const {
    return impl_->sim->minimising();
}
std::optional<FireState> Run::minimiserState() const {
    return impl_->sim->minimiserState();
}
const Construction& Run::construction() const {
    return impl_->sim->construction();
}

void Run::reseat(const Particles& all, const Construction& construction, long long step) {
    Impl& i = *impl_;
    const StepTimes times = i.sim->times();
    SimulationOptions o = i.options;
    o.construction = construction;
    o.firstStep = step;
    o.params = i.sim->params();  // the weights, drags and probe that commands set
    o.cuts = i.sim->cuts();      // the maps and bonds as cuts left them
    o.yields = i.sim->yields();  // and as dents that yielded left them
    i.carriedMigrations += double(i.ex->counts().migrations);
    i.carriedRebuilds += double(i.sim->rebuilds());
    i.carriedExchange += i.sim->exchangeSeconds();
    i.carriedRebalances += double(i.ex->counts().rebalances);
    const std::optional<FireState> fire = i.sim->minimiserState();
    i.start(all, std::move(o));
    if (fire) i.sim->minimise(i.fire, fire);
    i.sim->setTimes(times);
    i.sim->setEnergyEvery(i.energyEvery);
    i.keepIfSound();
}
void Run::setProbe(const ProbeState& probe) {
    impl_->sim->probe() = probe;
}
Totals Run::totals() const {
    return impl_->sim->totals();
}
ShapeCounts Run::shapeCounts() const {
    const Simulation& s = *impl_->sim;
    const Model& m = s.model();
    const GradientMap* map = s.mapInForce().map().get();
    std::vector<double> mine(4, 0.0);  // surface, surface in own voxels, volume, volume in own voxels
    const Particles& p = s.particles();
    const double h = map ? voxelLength(map->r0Voxels) : 1.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = m.isSurface(p.species[i]) ? 0 : 2;
        mine[k] += 1;
        if (!map) continue;
        const std::int64_t v = map->voxelHolding(p.pos[i] / h);
        mine[k + 1] += v >= 0 && map->occ[std::size_t(v)] == p.species[i] ? 1 : 0;
    }
    ShapeCounts out;
    const std::vector<double> all = impl_->ex->allGather(mine);
    for (std::size_t k = 0; k < all.size(); k += 4) {
        out.surface += all[k];
        out.surfaceInOwn += all[k + 1];
        out.volume += all[k + 2];
        out.volumeInOwn += all[k + 3];
    }
    return out;
}
const std::vector<MapVolume>& Run::frameVolumes() const {
    return impl_->sim->frameVolumes();
}
Particles Run::gather() const {
    return impl_->sim->gather();
}
void Run::submit(const Command& command) {
    impl_->sim->submit(command);
}
bool Run::commandsQueued() const {
    return impl_->sim->commandsQueued();
}
long long Run::stepNumber() const {
    return impl_->sim->stepCount();
}

Run::Decision Run::agree(const Decision& mine) {
    std::vector<Decision> v{mine};
    impl_->ex->broadcastRecords(v);
    if (v.size() != 1)
        throw std::runtime_error("run loop: rank 0's decision came as " + std::to_string(v.size()) + " records");
    return v[0];
}

namespace {

// A position as a frame carries it: in the periodic box, [lo, hi) in float too (between list
// rebuilds the run keeps particles that crossed a periodic face on the far side).
std::array<float, 3> framePosition(const Box& box, const Eigen::Vector3d& x) {
    const Eigen::Vector3d w = box.wrap(x);
    std::array<float, 3> f{float(w.x()), float(w.y()), float(w.z())};
    for (std::size_t a = 0; a < 3; ++a)
        if (box.periodic[a] && f[a] >= float(box.hi[int(a)]))
            f[a] = std::nextafter(float(box.hi[int(a)]), float(box.lo[int(a)]));
    return f;
}

}  // namespace

void Run::gatherFrame(FrameArrays& f) const {
    const Particles& p = impl_->sim->particles();
    const Box& box = impl_->model->box;
    if (size() == 1) {  // straight into the frame's arrays
        const std::size_t n = p.size();
        f.positions.resize(3 * n);
        f.normals.resize(3 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const std::array<float, 3> x = framePosition(box, p.pos[i]);
            for (int a = 0; a < 3; ++a) {
                f.positions[3 * i + std::size_t(a)] = x[std::size_t(a)];
                f.normals[3 * i + std::size_t(a)] = float(p.normal[i][a]);
            }
        }
        f.species.assign(p.species.begin(), p.species.end());
        f.ids.assign(p.id.begin(), p.id.end());
        return;
    }
    // One record per particle, in rank order on rank 0.
    struct FrameRecord {
        std::array<float, 3> pos, normal;
        std::uint64_t id;
        std::uint8_t species;
    };
    std::vector<FrameRecord> mine;
    mine.reserve(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
        mine.push_back({framePosition(box, p.pos[i]),
                        {float(p.normal[i].x()), float(p.normal[i].y()), float(p.normal[i].z())},
                        p.id[i],
                        p.species[i]});
    const std::vector<FrameRecord> all = impl_->ex->gatherV(mine);
    const std::size_t n = all.size();
    f.positions.resize(3 * n);
    f.normals.resize(3 * n);
    f.species.resize(n);
    f.ids.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        std::copy_n(all[k].pos.data(), 3, &f.positions[3 * k]);
        std::copy_n(all[k].normal.data(), 3, &f.normals[3 * k]);
        f.species[k] = all[k].species;
        f.ids[k] = all[k].id;
    }
}

int Run::rank() const {
    return impl_->ex->rank();
}
int Run::size() const {
    return impl_->ex->size();
}
std::array<int, 3> Run::grid() const {
    return impl_->ex->grid();
}
const Simulation& Run::simulation() const {
    return *impl_->sim;
}
const Params& Run::paramsAhead() const {
    return impl_->sim->paramsAhead();
}
Simulation& Run::simulation() {
    return *impl_->sim;
}
const Exchange& Run::exchange() const {
    return *impl_->ex;
}

RunCounters Run::counters() const {
    const auto& s = *impl_->sim;
    const Exchange::Counts x = impl_->ex->counts();
    const Impl& i = *impl_;
    // This rank's share, one record per rank in rank order.
    struct Share {
        double haloBytes, migrations, rebuilds, particles, exchangeSeconds, mapBytes;
    };
    const Share mine{double(x.haloBytesPerStep),
                     double(x.migrations) + i.carriedMigrations,
                     double(s.rebuilds()) + i.carriedRebuilds,
                     double(s.particles().size()),
                     s.exchangeSeconds() + i.carriedExchange,
                     double(s.mapBytes())};
    RunCounters c;
    double most = 0, sum = 0;
    for (const Share& rank : impl_->ex->allGather(std::vector{mine})) {
        c.exchangeSecondsMax = std::max(c.exchangeSecondsMax, rank.exchangeSeconds);
        c.mapBytesMax = std::max(c.mapBytesMax, rank.mapBytes);
        c.haloBytesPerStep += rank.haloBytes;
        c.migrations += rank.migrations;
        c.rebuilds = rank.rebuilds;  // the same on every rank
        most = std::max(most, rank.particles);
        sum += rank.particles;
    }
    c.imbalance = sum > 0 ? most * double(size()) / sum : 1.0;
    c.initialImbalance = x.initialImbalance;
    c.rebalances = double(x.rebalances) + i.carriedRebalances;
    c.births = double(s.construction().totals().births);
    c.deaths = double(s.construction().totals().deaths);
    return c;
}

}  // namespace bop::core
