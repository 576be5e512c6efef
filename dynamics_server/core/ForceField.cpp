#include "ForceField.hpp"

#include "Stopwatch.hpp"

namespace bop::core {

ForceField::ForceField(const Model& model, const Params& params, bool map) : pairs_(model, params, map) {}

void ForceField::compute(const Model& model, const MapInForce& maps, const ProbeState& probe, Particles& p,
                         ForceStats& stats, PhaseTimes* times, bool energies, const Halo* halo) {
    stats = ForceStats{};
    auto t0 = PhaseClock::now();
    map_.setBlend(maps.next(), maps.at.w);
    map_.set(model, maps.map(), p, stats, pairs_.oriented());  // curvature weights serve the co-planar pairs only
    if (times) times->gradientMap += secondsSince(t0);
    pairs_.add(model, maps, p, halo, map_.curvatureWeights(), stats, energies, times);
    t0 = PhaseClock::now();
    probeForces(model, probe, p, stats);
    if (times) times->probe += secondsSince(t0);
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
