#include "control/ForceModel.hpp"

#include <algorithm>

namespace bop::haptic {

double silenceGain(const ForceModelParams& p, double since) {
    if (since <= p.silenceS) return 1;
    return std::max(0.0, 1 - (since - p.silenceS) / p.rampDownS);
}

ForceModel::ForceModel(ForceModelParams p, std::function<Eigen::Vector3d(const Eigen::Vector3d&)> field)
    : p_(p), field_(std::move(field)) {}

void ForceModel::reset(const Eigen::Vector3d& at) {
    proxy_ = device_ = at;
    proxyV_.setZero();
    started_ = true;
}

void ForceModel::feedback(const Eigen::Vector3d& reaction, double t) {
    server_ = reaction;
    if (!lastFeedbackS_ || t - *lastFeedbackS_ > p_.silenceS) {  // first feedback, or back after a silence
        resumedAtS_ = t;
        gainAtResume_ = gain_;
    }
    lastFeedbackS_ = t;
}

ForceOutput ForceModel::tick(double t, double dt, const Eigen::Vector3d& device) {
    if (!started_) reset(device);
    const Eigen::Vector3d deviceV = dt > 0 ? Eigen::Vector3d((device - device_) / dt) : Eigen::Vector3d::Zero();
    device_ = device;
    ForceOutput out;
    out.feedbackAgeS = lastFeedbackS_ ? t - *lastFeedbackS_ : 1e300;
    // Without feedback the server's reaction is unknown: none is applied to the proxy.
    out.server = out.feedbackAgeS <= p_.silenceS ? server_ : Eigen::Vector3d::Zero();
    out.field = field_ ? field_(proxy_) : Eigen::Vector3d::Zero();
    // Implicit Euler for the proxy: m dv = dt [k (xd - xp - dt v') + b (vd - v') + F].
    const double m = p_.proxyMass, k = p_.stiffness, b = p_.damping;
    const Eigen::Vector3d rhs = m * proxyV_ + dt * (k * (device - proxy_) + b * deviceV + out.server + out.field);
    proxyV_ = rhs / (m + dt * b + dt * dt * k);
    proxy_ += dt * proxyV_;
    out.proxy = proxy_;
    // Safety: down within rampDown after silenceS without feedback; up over rampUp when it returns.
    const double down = lastFeedbackS_ ? silenceGain(p_, out.feedbackAgeS) : 0.0;
    const double up = gainAtResume_ + (1 - gainAtResume_) * std::clamp((t - resumedAtS_) / p_.rampUpS, 0.0, 1.0);
    gain_ = std::min(down, up);
    out.gain = gain_;
    out.force = -gain_ * (k * (device - proxy_) + b * (deviceV - proxyV_));
    return out;
}

}  // namespace bop::haptic
