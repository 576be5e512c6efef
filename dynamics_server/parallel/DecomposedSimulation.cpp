#include "DecomposedSimulation.hpp"

#include "Packing.hpp"

#include "core/BloodPressure.hpp"
#include "core/SoundState.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace bop::parallel {
namespace {

// The widest halo a run needs: the pair terms' list range, or the birth front of construction.
double haloReach(const core::Model& model, const core::ForceField& field, const DecomposedOptions& o) {
    const double front = o.construction ? o.construction->params().frontR0 : core::ConstructionParams{}.frontR0;
    return std::max(field.listRange(), model.map || o.map ? front * core::kR0 : 0.0);
}

}  // namespace

DecomposedSimulation::DecomposedSimulation(const CartComm& comm, std::shared_ptr<const core::Model> model,
                                           const core::Particles& all, DecomposedOptions options)
    : comm_(comm), model_(std::move(model)), field_(*model_),
      dec_(model_->box, comm.dims(), haloReach(*model_, field_, options)), sub_(*model_), drag_(*model_),
      range_(field_.listRange()), step_(options.firstStep),
      construction_(options.construction ? *options.construction
                                         : core::Construction({}, {}, model_->speciesCount())),
      mapSource_(std::move(options.map)) {
    if (!mapSource_ && model_->map) {
        GradientMap header = *model_->map;
        header.occ = {}, header.nearest = {}, header.surface = {};
        std::vector<std::shared_ptr<const GradientMap>> frames = model_->frames;
        if (frames.size() < 2) frames = {model_->map};
        const int count = int(frames.size());
        mapSource_ = MapSource{std::move(header),
                               [frames = std::move(frames)](int f, const shape::VoxelWindow& w) {
                                   return shape::cropGradientMap(*frames.at(std::size_t(f)), w);
                               },
                               count};
    }
    sub_.map = nullptr;
    sub_.frames.clear();
    sub_.box = dec_.subdomain(comm_.coords());
    cropMap();
    if (mapSource_) {  // whole-map voxel counts: each rank counts the voxel centres in its subdomain
        std::vector<double> mine;
        for (const auto& f : subFrames_) {
            const core::MapVolume v = core::countMapVolume(*f, sub_.box.lo, sub_.box.hi);
            mine.insert(mine.end(), {v.bagVoxels, v.volumeVoxels});
        }
        const std::vector<double> counts = comm_.allGather(mine);
        frameVolumes_.assign(subFrames_.size(), {});
        for (std::size_t k = 0; k < counts.size(); ++k) {  // rank order: the same sums everywhere
            core::MapVolume& v = frameVolumes_[(k % mine.size()) / 2];
            (k % 2 ? v.volumeVoxels : v.bagVoxels) += counts[k];
        }
    }
    field_ = core::ForceField(sub_);  // with the map window: the pair terms' curvature weights need to know of a map
    applyKeyframe(double(step_) * model_->integration.dt);
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (!mine(all.pos[i])) continue;
        const std::size_t k = p_.add(all.pos[i], all.species[i], all.id[i], all.q[i]);
        p_.q[k] = all.q[i];
        p_.normal[k] = all.normal[i];
        p_.vel[k] = all.vel[i];
        p_.omega[k] = all.omega[i];
    }
    initialImbalance_ = imbalanceNow();
    rebalance();
    forces(true);
    kinetic_ = core::kineticEnergy(sub_, p_);
}

void DecomposedSimulation::cropMap() {
    if (!mapSource_) return;
    const GradientMap& whole = mapSource_->header;
    const double h = core::kR0 / whole.r0Voxels;
    // Owned particles stray up to about half the skin out of the subdomain between rebuilds,
    // ghosts (whose curvature weights the pair terms read) up to the list range beyond it;
    // the trilinear rule reads one voxel further.
    const double margin = 1.5 * range_ + 2 * h;
    const shape::VoxelWindow w = shape::windowAround(whole.dims(), h, sub_.box.lo, sub_.box.hi, margin);
    if (sub_.map && w.lo == window_.lo && w.hi == window_.hi) return;
    window_ = w;
    // The new windows are made while the old ones live, so the force field, which notices a
    // new map by its address, cannot mistake one for the other.
    std::vector<std::shared_ptr<const GradientMap>> next;
    for (int f = 0; f < mapSource_->frames; ++f) next.push_back(std::make_shared<const GradientMap>(mapSource_->crop(f, w)));
    subFrames_ = std::move(next);
    sub_.map = subFrames_[std::size_t(keyframe_.a)];
    field_.setMapBlend(subFrames_[std::size_t(keyframe_.b)].get(), keyframe_.w);  // not the old window's
}

void DecomposedSimulation::applyKeyframe(double time) {
    if (!mapSource_) return;
    const bool animated = model_->keyframes.animated() && subFrames_.size() > 1;
    keyframe_ = animated ? model_->keyframes.at(time) : core::KeyframeAt{};
    sub_.map = subFrames_[std::size_t(keyframe_.a)];
    field_.setMapBlend(subFrames_[std::size_t(keyframe_.b)].get(), keyframe_.w);
}

std::size_t DecomposedSimulation::mapBytes() const {
    std::size_t bytes = 0;
    for (const auto& f : subFrames_) bytes += shape::gradientMapBytes(*f);  // every keyframe's window
    return bytes;
}

void DecomposedSimulation::forces(bool energies) {
    field_.compute(sub_, probe_, p_, stats_, &times_, energies, &halo_);
}

void DecomposedSimulation::refreshForces() {
    forces(true);
}

void DecomposedSimulation::setWeight(core::Model& m, const Command& c) {
    if (c.other < 1 || c.other > m.speciesCount())
        throw std::invalid_argument("weight command: no species " + std::to_string(c.other));
    if (c.species < 1 || c.species > m.speciesCount())
        throw std::invalid_argument("weight command: no species " + std::to_string(c.species));
    if (!std::isfinite(c.value) || c.value < 0) throw std::invalid_argument("weight command: weights must be 0 or more");
    core::WeightMatrix& w = c.table == Command::Table::Lj ? m.lj : c.table == Command::Table::CoNormal ? m.coNormal : m.coPlanar;
    w(c.species, c.other) = c.value;
}

void DecomposedSimulation::submit(const Command& command) {
    if (comm_.rank() != 0) throw std::logic_error("commands are submitted on rank 0");
    if (command.kind == Command::Kind::Weight) {  // refused here, before any rank sees it
        core::Model trial = sub_;
        setWeight(trial, command);
        if (core::ForceField(trial).listRange() != range_)
            throw std::invalid_argument("weight command: it would change the interaction range (oriented terms on or "
                                        "off); give the scene a nonzero weight of that kind to start with");
    }
    encode(command, commands_);
}

void DecomposedSimulation::apply(const Command& c) {
    if (c.kind == Command::Kind::Probe) {
        probe_ = c.probe;
        return;
    }
    if (c.species < 1 || c.species > sub_.speciesCount())
        throw std::invalid_argument("command: no species " + std::to_string(c.species));
    if (c.kind == Command::Kind::Birth) {
        construction_.setBirth(c.species, c.on);
        return;
    }
    if (c.kind == Command::Kind::Weight) {
        setWeight(sub_, c);
        field_ = core::ForceField(sub_);  // its pair kernel keeps the weights; the new one builds its list afresh
        forcesStale_ = true;
        return;
    }
    if (!(c.dragV >= 0 && c.dragW >= 0)) throw std::invalid_argument("drag command: drags must be 0 or more");
    sub_.species[std::size_t(c.species)].dragV = c.dragV;
    sub_.species[std::size_t(c.species)].dragW = c.dragW;
    drag_ = core::DragFactors(sub_);
}

void DecomposedSimulation::step() {
    comm_.broadcast(commands_);  // rank 0's queue, the same on every rank
    // Construction first, as a single process does it: the timeline's events, then seeds
    // commanded, then a birth/death check when one is due.
    std::vector<core::ConstructionEvent> events = construction_.eventsAt(step_);
    for (const Command& c : decode(commands_)) {
        if (c.kind != Command::Kind::Seed) {
            apply(c);
            continue;
        }
        if (c.species < 1 || c.species > sub_.speciesCount())
            throw std::invalid_argument("seed command: no species " + std::to_string(c.species));
        core::ConstructionEvent e;
        e.step = step_;
        e.species = c.species;
        e.positionVoxels = c.position / (mapSource_ ? core::kR0 / mapSource_->header.r0Voxels : 1.0);
        events.push_back(e);
    }
    commands_.clear();
    applyKeyframe(double(step_ + 1) * model_->integration.dt);  // the time of this step's forces
    if (forcesStale_) forces(true);  // the step starts from forces of today's weights, as a single process's does
    forcesStale_ = false;
    construct(std::move(events));
    core::kickDrift(sub_, drag_, p_, false);
    const bool holds = field_.listHolds(sub_, p_);
    const auto t0 = std::chrono::steady_clock::now();
    if (!comm_.allTrue(holds)) {
        migrateHome();
        if (imbalanceNow() > 1.1) {
            rebalance();
        } else {
            buildHalo(range_);
            field_.requestRebuild();
        }
        ++rebuilds_;
    } else {
        updateHalo();
    }
    exchangeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++step_;
    forces(step_ % energyEvery_ == 0);
    kinetic_ = core::kick(sub_, drag_, p_);
    if (!comm_.allTrue(core::sound(*model_, p_, stats_.probeReaction))) throwUnsound();
}

void DecomposedSimulation::throwUnsound() const {
    // What each rank found, so that every rank throws the same words: the first rank's finding.
    const core::Unsoundness mine = core::findUnsound(*model_, p_, stats_.probeReaction);
    const std::vector<double> all = comm_.allGather({double(mine.what), double(mine.id & 0xffffffffu),
                                                     double(mine.id >> 32), double(mine.species)});
    for (std::size_t r = 0; r < all.size(); r += 4) {
        if (all[r] == 0) continue;
        const core::Unsoundness u{core::Unsoundness::What(int(all[r])),
                                  std::uint64_t(all[r + 1]) | std::uint64_t(all[r + 2]) << 32, int(all[r + 3])};
        throw core::UnsoundState(step_, u.text() + " (rank " + std::to_string(r / 4) + ")");
    }
    throw core::UnsoundState(step_, "on a rank that could not say where");
}

Totals DecomposedSimulation::totals() const {
    const auto& f = stats_;
    const core::BloodSums blood = core::bloodSums(sub_, p_);
    const std::vector<double> mine{double(p_.size()), kinetic_, f.pairEnergy, f.probeEnergy, f.virial, f.virialVolume,
                                   f.probeReaction.x(), f.probeReaction.y(), f.probeReaction.z(), blood.mv2,
                                   blood.count, f.wallVirial};
    const std::vector<double> all = comm_.allGather(mine);
    std::vector<double> sum(mine.size(), 0.0);
    for (std::size_t r = 0; r < std::size_t(comm_.size()); ++r)  // rank order: the same sum everywhere
        for (std::size_t k = 0; k < mine.size(); ++k) sum[k] += all[r * mine.size() + k];
    Totals t;
    t.particles = sum[0];
    t.kinetic = sum[1];
    t.pairEnergy = sum[2];
    t.probeEnergy = sum[3];
    t.virial = sum[4];
    t.virialVolume = sum[5];
    t.probeReaction = Eigen::Vector3d(sum[6], sum[7], sum[8]);
    t.bloodMv2 = sum[9];
    t.bloodCount = sum[10];
    t.wallVirial = sum[11];
    t.keyframe = keyframe_;
    if (mapSource_) {
        const double h3 = std::pow(core::kR0 / mapSource_->header.r0Voxels, 3);
        std::vector<double> blood, cavity;
        for (const core::MapVolume& v : frameVolumes_) blood.push_back(v.volumeVoxels), cavity.push_back(v.bagVoxels);
        t.bloodVolume = core::blendFrames(blood, keyframe_) * h3;
        t.cavityVolume = core::blendFrames(cavity, keyframe_) * h3;
    }
    return t;
}

core::Particles DecomposedSimulation::gather() const { return gather(p_); }

bool DecomposedSimulation::soundEverywhere() const { return comm_.allTrue(core::sound(*model_, p_, stats_.probeReaction)); }

core::Particles DecomposedSimulation::gather(const core::Particles& p) const {
    constexpr int kFields = kMigrateFields + 6;  // and force 3, torque 3
    std::vector<double> mine;
    for (std::size_t i = 0; i < p.size(); ++i) {
        packParticle(p, i, mine);
        mine.insert(mine.end(), {p.force[i].x(), p.force[i].y(), p.force[i].z(), p.torque[i].x(), p.torque[i].y(),
                                 p.torque[i].z()});
    }
    const std::vector<double> all = comm_.allGatherV(mine);
    std::vector<std::size_t> order(all.size() / kFields);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return idOf(all[a * kFields + 14]) < idOf(all[b * kFields + 14]); });
    core::Particles out;
    for (std::size_t k : order) {
        const double* v = &all[k * kFields];
        unpackParticles(std::vector<double>(v, v + kMigrateFields), out);
        out.force.back() = Eigen::Vector3d(v[15], v[16], v[17]);
        out.torque.back() = Eigen::Vector3d(v[18], v[19], v[20]);
    }
    return out;
}

}  // namespace bop::parallel
