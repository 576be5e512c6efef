#include "Fire.hpp"

#include "Threads.hpp"

#include <algorithm>
#include <cmath>

namespace bop::core {

FirePower firePower(const Model& model, const Particles& p) {
    const std::array<double, 5> s = sumsIndex<5>(p.size(), [&](std::size_t i) {
        const double fv = p.force[i].dot(p.vel[i]), vv = p.vel[i].squaredNorm(), ff = p.force[i].squaredNorm();
        if (!model.isSurface(p.species[i])) return std::array<double, 5>{fv, vv, ff, 0.0, 0.0};
        return std::array<double, 5>{fv + p.torque[i].dot(p.omega[i]), vv, ff, p.omega[i].squaredNorm(),
                                     p.torque[i].squaredNorm()};
    });
    return {s[0], s[1], s[2], s[3], s[4]};
}

Fire::Fire(const FireParams& params, double dt, const std::optional<FireState>& from)
    : params_(params), dt0_(dt), dt_(dt), alpha_(params.alphaStart) {
    if (!from) return;
    dt_ = from->dt;
    alpha_ = from->alpha;
    steps_ = from->steps;
    sincePositive_ = from->sincePositive;
}

FireKick Fire::next(const FirePower& s) {
    ++steps_;
    FireKick k;
    if (s.power > 0) {
        if (++sincePositive_ > params_.delaySteps) {
            dt_ = std::min(dt_ * params_.grow, params_.dtMaxFactor * dt0_);
            alpha_ *= params_.alphaShrink;
        }
        k.keep = 1.0 - alpha_;
        k.alongForce = s.ff > 0 ? alpha_ * std::sqrt(s.vv / s.ff) : 0.0;
        k.alongTorque = s.tt > 0 ? alpha_ * std::sqrt(s.ww / s.tt) : 0.0;
    } else {
        sincePositive_ = 0;
        // The first steps start from rest, where the power is zero: no cut while they last.
        if (steps_ > params_.delaySteps) {
            dt_ = std::max(dt_ * params_.shrink, params_.dtMinFactor * dt0_);
            alpha_ = params_.alphaStart;
        }
        k.stop = true;
        k.back = 0.5 * dt_;
    }
    k.dt = dt_;
    return k;
}

}  // namespace bop::core
