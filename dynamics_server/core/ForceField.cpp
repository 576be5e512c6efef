#include "ForceField.hpp"

#include <chrono>

namespace bop::core {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

ForceField::ForceField(const Model& model)
    : kernel_(model), isVolume_(std::size_t(model.speciesCount()) + 1, 0), cellSize_(kernel_.cutoff()) {
    for (int s = 1; s <= model.speciesCount(); ++s) isVolume_[std::size_t(s)] = !model.isSurface(s);
}

void ForceField::compute(const Model& model, const ProbeState& probe, Particles& p, ForceStats& stats,
                         PhaseTimes* times, bool energies) {
    stats = ForceStats{};
    for (std::size_t i = 0; i < p.size(); ++i) {
        p.force[i].setZero();
        p.torque[i].setZero();
    }
    auto t0 = Clock::now();
    gradientMapForces(model, p);
    if (times) times->gradientMap += since(t0);
    t0 = Clock::now();
    cells_.build(model.box, cellSize_, p.pos);
    if (times) times->cells += since(t0);
    t0 = Clock::now();
    pairForces(p, stats, energies);
    if (times) times->pairs += since(t0);
    t0 = Clock::now();
    probeForces(model, probe, p, stats);
    if (times) times->probe += since(t0);
}

void ForceField::gradientMapForces(const Model& model, Particles& p) {
    cpWeight_.assign(p.size(), 1.0f);
    if (!model.map) return;
    if (fieldMap_ != model.map.get()) {
        field_ = std::make_unique<shape::GmField>(*model.map, model.interpolation);
        fieldMap_ = model.map.get();
    }
    const GradientMap& map = *model.map;
    const Dims& d = map.dims();
    const double h = field_->voxelSize();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Species& sp = model.species[p.species[i]];
        const shape::GmSample g = field_->sample(sp.kind, p.species[i], p.pos[i], p.normal[i]);
        p.force[i] += sp.alphaForceGm * g.force;
        if (sp.kind == ParticleKind::Surface) {
            p.torque[i] += sp.alphaTorqueGm * g.torque;
            const Eigen::Vector3i v = (p.pos[i] / h).array().floor().cast<int>().max(0).min(
                Eigen::Array3i(d.nx - 1, d.ny - 1, d.nz - 1)).matrix();
            cpWeight_[i] = map.nearestSurface(d.index(v.x(), v.y(), v.z())).cpWeight;
        }
    }
}

void ForceField::pairForces(Particles& p, ForceStats& stats, bool energies) {
    PairKernel& kernel = kernel_;
    kernel.setEnergy(energies);
    const auto& order = cells_.order();
    const std::size_t n = p.size();
    sp_.resize(n); sn_.resize(n); ss_.resize(n); sw_.resize(n);
    sf_.assign(n, Eigen::Vector3d::Zero());
    st_.assign(n, Eigen::Vector3d::Zero());
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t i = order[k];
        sp_[k] = p.pos[i]; sn_[k] = p.normal[i]; ss_[k] = p.species[i]; sw_[k] = cpWeight_[i];
    }
    PairKernel::Sums sums;
    std::array<CellList::Neighbour, 14> stencil;
    const double cut2 = kernel.cutoff2();
    for (int c = 0; c < cells_.cellCount(); ++c) {
        const std::uint32_t b0 = cells_.start(c), b1 = cells_.start(c + 1);
        if (b0 == b1) continue;
        const int m = cells_.halfStencil(c, stencil);
        for (int s = 0; s < m; ++s) {
            const std::uint32_t e0 = cells_.start(stencil[s].cell), e1 = cells_.start(stencil[s].cell + 1);
            const Eigen::Vector3d shift = stencil[s].shift;
            for (std::uint32_t i = b0; i < b1; ++i) {
                const Eigen::Vector3d pi = sp_[i] - shift;
                const int a = ss_[i];
                for (std::uint32_t j = (s == 0 ? i + 1 : e0); j < e1; ++j) {
                    const Eigen::Vector3d r = sp_[j] - pi;
                    const double r2 = r.squaredNorm();
                    if (r2 >= cut2) continue;
                    kernel.apply(i, j, a, ss_[j], r, r2, sn_[i], sn_[j], sw_[i], sw_[j], sf_.data(), st_.data(),
                                 isVolume_[std::size_t(a)], isVolume_[ss_[j]], sums);
                }
            }
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        p.force[order[k]] += sf_[k];
        p.torque[order[k]] += st_[k];
    }
    stats.pairEnergy = sums.energy;
    stats.virial = sums.virial;
    stats.virialVolume = sums.virialVolume;
    stats.pairsInRange = sums.inRange;
}

void ForceField::computePairsBruteForce(const Model& model, Particles& p, ForceStats& stats) {
    const PairKernel kernel(model);
    std::vector<float> w(p.size(), 1.0f);
    PairKernel::Sums sums;
    const Eigen::Vector3d L = model.box.size();
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j) {
            Eigen::Vector3d r = p.pos[j] - p.pos[i];
            for (int a = 0; a < 3; ++a)
                if (model.box.periodic[std::size_t(a)]) r[a] -= L[a] * std::round(r[a] / L[a]);
            kernel.apply(i, j, p.species[i], p.species[j], r, r.squaredNorm(), p.normal[i], p.normal[j], w[i], w[j],
                         p.force.data(), p.torque.data(), !model.isSurface(p.species[i]), !model.isSurface(p.species[j]),
                         sums);
        }
    stats.pairEnergy = sums.energy;
    stats.virial = sums.virial;
    stats.virialVolume = sums.virialVolume;
    stats.pairsInRange = sums.inRange;
}

void ForceField::probeForces(const Model& model, const ProbeState& probe, Particles& p, ForceStats& stats) {
    if (!probe.active) return;
    const ProbeForm form(LjForm(model.ljParams), probe.params);
    const double cut2 = form.cutoff() * form.cutoff();
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector3d r = p.pos[i] - probe.position;
        const double r2 = r.squaredNorm();
        if (r2 >= cut2) continue;
        double fOverR, e;
        if (!form.eval(r2, fOverR, e)) continue;
        p.force[i] += fOverR * r;
        stats.probeReaction -= fOverR * r;
        stats.probeEnergy += e;
    }
}

}  // namespace bop::core
