#include "ForceField.hpp"

#include "Stopwatch.hpp"

#include <cmath>

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
    if (model.probeSphere) {
        sphereProbeForces(*model.probeSphere, probe.position, p, stats);
        return;
    }
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

void sphereProbeForces(const ProbeSphere& sphere, const Eigen::Vector3d& centre, Particles& p, ForceStats& stats) {
    const double r2max = sphere.radius * sphere.radius;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Eigen::Vector3d r = p.pos[i] - centre;
        const double r2 = r.squaredNorm();
        if (r2 >= r2max || r2 == 0.0) continue;
        const double d = std::sqrt(r2);
        const double overlap = sphere.radius - d;
        const Eigen::Vector3d f = (sphere.stiffness * overlap / d) * r;
        p.force[i] += f;
        stats.probeReaction -= f;
        stats.probeEnergy += 0.5 * sphere.stiffness * overlap * overlap;
    }
}

}  // namespace bop::core
