#include "DecomposedSimulation.hpp"

#include "Packing.hpp"

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

constexpr int kMigrateFields = 15;  // pos 3, vel 3, q 4, omega 3, species, id
constexpr int kGhostFields = 8;     // pos 3, normal 3, species, id
constexpr int kUpdateFields = 6;    // pos 3, normal 3

// The widest halo a run needs: the pair terms' list range, or the birth front of construction.
double haloReach(const core::Model& model, const core::ForceField& field, const DecomposedOptions& o) {
    const double front = o.construction ? o.construction->params().frontR0 : core::ConstructionParams{}.frontR0;
    return std::max(field.listRange(), model.map || o.map ? front * core::kR0 : 0.0);
}

void packParticle(const core::Particles& p, std::size_t i, std::vector<double>& out) {
    const auto& q = p.q[i];
    out.insert(out.end(), {p.pos[i].x(), p.pos[i].y(), p.pos[i].z(), p.vel[i].x(), p.vel[i].y(), p.vel[i].z(), q.w(),
                           q.x(), q.y(), q.z(), p.omega[i].x(), p.omega[i].y(), p.omega[i].z(), double(p.species[i]),
                           idBits(p.id[i])});
}

void unpackParticles(const std::vector<double>& in, core::Particles& p) {
    for (std::size_t k = 0; k + kMigrateFields <= in.size(); k += kMigrateFields) {
        const double* v = &in[k];
        const std::size_t i = p.add(Eigen::Vector3d(v[0], v[1], v[2]), int(v[13]), idOf(v[14]),
                                    Eigen::Quaterniond(v[6], v[7], v[8], v[9]));
        p.q[i] = Eigen::Quaterniond(v[6], v[7], v[8], v[9]);  // bit for bit, not renormalised
        p.normal[i] = p.q[i] * Eigen::Vector3d::UnitZ();
        p.vel[i] = Eigen::Vector3d(v[3], v[4], v[5]);
        p.omega[i] = Eigen::Vector3d(v[10], v[11], v[12]);
    }
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
        mapSource_ = MapSource{std::move(header), [map = model_->map](const shape::VoxelWindow& w) {
                                   return shape::cropGradientMap(*map, w);
                               }};
    }
    sub_.map = nullptr;
    sub_.box = dec_.subdomain(comm_.coords());
    cropMap();
    field_ = core::ForceField(sub_);  // with the map window: the pair terms' curvature weights need to know of a map
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
    // The new window is made while the old one lives, so the force field, which notices a new
    // map by its address, cannot mistake one for the other.
    auto next = std::make_shared<const GradientMap>(mapSource_->crop(w));
    sub_.map = std::move(next);
}

std::size_t DecomposedSimulation::mapBytes() const {
    return sub_.map ? shape::gradientMapBytes(*sub_.map) : 0;
}

double DecomposedSimulation::imbalanceNow() const {
    return Decomposition::imbalance(comm_.allGather({double(p_.size())}));
}

void DecomposedSimulation::migrateHome() {
    // One hop per axis per pass; moved planes, or a particle faster than half the skin per step,
    // can put a particle several subdomains away.
    const int passes = std::max({comm_.dims()[0], comm_.dims()[1], comm_.dims()[2]});
    for (int pass = 0; pass < passes; ++pass) {
        wrapAndMigrate();
        bool here = true;
        for (const auto& x : p_.pos) here = here && dec_.owner(x) == comm_.coords();
        if (comm_.allTrue(here)) return;
    }
}

void DecomposedSimulation::rebalance() {
    constexpr int kBins = 256;
    const core::Box& box = model_->box;
    const Eigen::Vector3d L = box.size();
    std::vector<double> local(3 * kBins, 0.0);
    for (const auto& x : p_.pos)
        for (int a = 0; a < 3; ++a) {
            double u = x[a];
            if (box.periodic[std::size_t(a)]) u -= L[a] * std::floor((u - box.lo[a]) / L[a]);
            const int b = std::clamp(int((u - box.lo[a]) / L[a] * kBins), 0, kBins - 1);
            local[std::size_t(a * kBins + b)] += 1;
        }
    const std::vector<double> all = comm_.allGather(local);  // whole counts: exact in any order
    std::array<std::vector<double>, 3> histogram;
    for (int a = 0; a < 3; ++a) {
        histogram[std::size_t(a)].assign(kBins, 0.0);
        for (std::size_t r = 0; r < std::size_t(comm_.size()); ++r)
            for (int b = 0; b < kBins; ++b) histogram[std::size_t(a)][std::size_t(b)] += all[r * local.size() + std::size_t(a * kBins + b)];
    }
    dec_.balance(histogram);
    sub_.box = dec_.subdomain(comm_.coords());
    cropMap();
    migrateHome();
    buildHalo(range_);
    field_.requestRebuild();
    ++rebalances_;
}

void DecomposedSimulation::wrapAndMigrate() {
    const core::Box& box = model_->box;
    const Eigen::Vector3d L = box.size();
    for (auto& x : p_.pos)
        for (int a = 0; a < 3; ++a)
            if (box.periodic[std::size_t(a)] && (x[a] < box.lo[a] || x[a] >= box.hi[a])) {
                x[a] -= L[a] * std::floor((x[a] - box.lo[a]) / L[a]);
                if (x[a] >= box.hi[a]) x[a] = box.lo[a];  // -1e-17 + L rounds to L: that is lo
            }
    for (int a = 0; a < 3; ++a) {
        if (comm_.dims()[std::size_t(a)] == 1) continue;
        std::vector<double> toLower, toUpper, fromUpper, fromLower;
        std::vector<char> leaves(p_.size(), 0);
        for (std::size_t i = 0; i < p_.size(); ++i) {
            const int c = dec_.owner(p_.pos[i])[std::size_t(a)], mine = comm_.coords()[std::size_t(a)];
            if (c == mine) continue;
            // One hop towards the owner (migrateHome() repeats while any particle is away); across
            // a periodic seam the owner's coordinate wraps, so there the nearer way round decides.
            const int n = comm_.dims()[std::size_t(a)];
            const int down = ((mine - c) % n + n) % n, up = ((c - mine) % n + n) % n;
            const bool lower = box.periodic[std::size_t(a)] ? down <= up : c < mine;
            if ((lower ? comm_.lower(a) : comm_.upper(a)) == MPI_PROC_NULL) continue;  // past an open face: stays
            packParticle(p_, i, lower ? toLower : toUpper);
            leaves[i] = 1;
            ++migrations_;
        }
        comm_.sendRecv(toLower, comm_.lower(a), fromUpper, comm_.upper(a), 100 + 4 * a);
        comm_.sendRecv(toUpper, comm_.upper(a), fromLower, comm_.lower(a), 102 + 4 * a);
        p_.removeIf(leaves);
        unpackParticles(fromUpper, p_);
        unpackParticles(fromLower, p_);
    }
}

void DecomposedSimulation::buildHalo(double range) {
    halo_ = core::Halo{};
    stages_.clear();
    haloBytes_ = 0;
    const core::Box& box = model_->box;
    const core::Box& mine = sub_.box;
    for (int a = 0; a < 3; ++a) {
        const int n = comm_.dims()[std::size_t(a)];
        if (n == 1) continue;
        Stage st;
        st.axis = a;
        const int c = comm_.coords()[std::size_t(a)];
        if (c == 0) st.lowerShift[a] = box.size()[a];       // lower neighbour lies across the periodic seam
        if (c == n - 1) st.upperShift[a] = -box.size()[a];  // so does the upper one
        const std::size_t sources = p_.size() + halo_.size();
        if (sources >= std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error("halo: more than 2^32 particles and ghosts on one rank; use more ranks");
        for (std::uint32_t s = 0; s < std::uint32_t(sources); ++s) {
            const double x = sourcePos(s)[a];
            if (x < mine.lo[a] + range) st.toLower.push_back(s);
            if (x >= mine.hi[a] - range) st.toUpper.push_back(s);
        }
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift) {
            std::vector<double> out;
            out.reserve(list.size() * kGhostFields);
            for (std::uint32_t s : list) {
                const bool own = s < p_.size();
                const Eigen::Vector3d x = sourcePos(s) + shift;
                const Eigen::Vector3d nrm = own ? p_.normal[s] : halo_.normal[s - p_.size()];
                const double species = own ? p_.species[s] : halo_.species[s - p_.size()];
                const std::uint64_t id = own ? p_.id[s] : halo_.id[s - p_.size()];
                out.insert(out.end(), {x.x(), x.y(), x.z(), nrm.x(), nrm.y(), nrm.z(), species, idBits(id)});
            }
            return out;
        };
        const auto append = [&](const std::vector<double>& in) {
            for (std::size_t k = 0; k + kGhostFields <= in.size(); k += kGhostFields) {
                halo_.pos.emplace_back(in[k], in[k + 1], in[k + 2]);
                halo_.normal.emplace_back(in[k + 3], in[k + 4], in[k + 5]);
                halo_.species.push_back(std::uint8_t(in[k + 6]));
                halo_.id.push_back(idOf(in[k + 7]));
            }
        };
        std::vector<double> fromUpper, fromLower;
        const std::vector<double> outLower = pack(st.toLower, st.lowerShift), outUpper = pack(st.toUpper, st.upperShift);
        comm_.sendRecv(outLower, comm_.lower(a), fromUpper, comm_.upper(a), 200 + 4 * a);
        comm_.sendRecv(outUpper, comm_.upper(a), fromLower, comm_.lower(a), 202 + 4 * a);
        haloBytes_ += ((comm_.lower(a) == MPI_PROC_NULL ? 0 : outLower.size()) +
                       (comm_.upper(a) == MPI_PROC_NULL ? 0 : outUpper.size())) * sizeof(double);
        st.fromUpperAt = halo_.size();
        st.fromUpperCount = fromUpper.size() / kGhostFields;
        append(fromUpper);
        st.fromLowerAt = halo_.size();
        st.fromLowerCount = fromLower.size() / kGhostFields;
        append(fromLower);
        if (comm_.lower(a) == MPI_PROC_NULL) st.toLower.clear();  // nothing was sent there
        if (comm_.upper(a) == MPI_PROC_NULL) st.toUpper.clear();
        stages_.push_back(std::move(st));
    }
}

void DecomposedSimulation::updateHalo() {
    haloBytes_ = 0;
    for (const Stage& st : stages_) {
        const auto pack = [&](const std::vector<std::uint32_t>& list, const Eigen::Vector3d& shift, std::vector<double>& out) {
            out.resize(list.size() * kUpdateFields);
            double* o = out.data();
            for (std::uint32_t s : list) {
                const Eigen::Vector3d x = sourcePos(s) + shift;
                const Eigen::Vector3d& nrm = s < p_.size() ? p_.normal[s] : halo_.normal[s - p_.size()];
                *o++ = x.x(); *o++ = x.y(); *o++ = x.z(); *o++ = nrm.x(); *o++ = nrm.y(); *o++ = nrm.z();
            }
        };
        const auto store = [&](const std::vector<double>& in, std::size_t at, std::size_t count) {
            if (in.size() != count * kUpdateFields) throw std::runtime_error("halo update: neighbour sent another ghost count");
            for (std::size_t k = 0; k < count; ++k) {
                halo_.pos[at + k] = Eigen::Vector3d(in[6 * k], in[6 * k + 1], in[6 * k + 2]);
                halo_.normal[at + k] = Eigen::Vector3d(in[6 * k + 3], in[6 * k + 4], in[6 * k + 5]);
            }
        };
        pack(st.toLower, st.lowerShift, out_[0]);
        pack(st.toUpper, st.upperShift, out_[1]);
        comm_.sendRecv(out_[0], comm_.lower(st.axis), in_[0], comm_.upper(st.axis), 300 + 4 * st.axis);
        comm_.sendRecv(out_[1], comm_.upper(st.axis), in_[1], comm_.lower(st.axis), 302 + 4 * st.axis);
        haloBytes_ += (out_[0].size() + out_[1].size()) * sizeof(double);
        store(in_[0], st.fromUpperAt, st.fromUpperCount);
        store(in_[1], st.fromLowerAt, st.fromLowerCount);
    }
}

void DecomposedSimulation::forces(bool energies) {
    field_.compute(sub_, probe_, p_, stats_, &times_, energies, &halo_);
}

void DecomposedSimulation::refreshForces() {
    forces(true);
}

void DecomposedSimulation::submit(const Command& command) {
    if (comm_.rank() != 0) throw std::logic_error("commands are submitted on rank 0");
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
}

Totals DecomposedSimulation::totals() const {
    const auto& f = stats_;
    const std::vector<double> mine{double(p_.size()), kinetic_, f.pairEnergy, f.probeEnergy, f.virial, f.virialVolume,
                                   f.probeReaction.x(), f.probeReaction.y(), f.probeReaction.z()};
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
    return t;
}

core::Particles DecomposedSimulation::gather() const {
    constexpr int kFields = kMigrateFields + 6;  // and force 3, torque 3
    std::vector<double> mine;
    for (std::size_t i = 0; i < p_.size(); ++i) {
        packParticle(p_, i, mine);
        mine.insert(mine.end(), {p_.force[i].x(), p_.force[i].y(), p_.force[i].z(), p_.torque[i].x(), p_.torque[i].y(),
                                 p_.torque[i].z()});
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
