#pragma once
// The force the device renders at 1 kHz (docs/haptics.md), closed over a local model, never over
// the network round trip. A proxy — a light virtual mass standing for the probe — is joined to
// the device by a spring and damper (the virtual coupling) and pushed by the newest reaction the
// server reported and by the gradient-map field at the proxy; the probe sent to the server is
// the proxy. The device feels the coupling's pull: in free space the proxy follows the device
// and the force is small; in contact the proxy stays at the surface and the user feels
// stiffness * (how far the hand went past it). Implicit integration keeps the coupling stable
// at any stiffness. A safety gain ramps the output to 0 when feedback stops and back up gently
// when it returns. Units: simulation length, force and mass; wall seconds.
#include <Eigen/Core>

#include <functional>
#include <optional>

namespace bop::haptic {

struct ForceModelParams {
    double stiffness = 10;     // coupling spring, force / length
    double damping = 0.1;      // coupling damper, force * s / length
    double proxyMass = 1e-3;   // mass; with the defaults the proxy follows the hand within ~10 ms
    double silenceS = 0.03;    // no feedback for this long: the server is taken as gone...
    double rampDownS = 0.015;  // ...and the output falls to 0 over this long (0.045 s after the last feedback)
    double rampUpS = 0.5;      // feedback back: the output rises from 0 over this long
};

struct ForceOutput {
    Eigen::Vector3d proxy = Eigen::Vector3d::Zero();   // the probe to send, length
    Eigen::Vector3d force = Eigen::Vector3d::Zero();   // on the device (the hand), force, gain applied
    Eigen::Vector3d server = Eigen::Vector3d::Zero();  // the reaction used, force
    Eigen::Vector3d field = Eigen::Vector3d::Zero();   // the gradient-map field at the proxy, force
    double gain = 0;                                   // safety gain 0..1
    double feedbackAgeS = 0;                           // since the newest feedback, s
};

class ForceModel {
public:
    // `field(x)`: the gradient-map field force at x (FieldForce.hpp), or none.
    explicit ForceModel(ForceModelParams p, std::function<Eigen::Vector3d(const Eigen::Vector3d&)> field = {});

    void feedback(const Eigen::Vector3d& reaction, double tS);  // the server's newest reaction arrived
    // One tick: the device (the hand) at `device` (length), `dtS` after the previous tick.
    ForceOutput tick(double tS, double dtS, const Eigen::Vector3d& device);

    const ForceModelParams& params() const { return p_; }
    void reset(const Eigen::Vector3d& at);  // proxy at rest at `at`

private:
    ForceModelParams p_;
    std::function<Eigen::Vector3d(const Eigen::Vector3d&)> field_;
    Eigen::Vector3d proxy_ = Eigen::Vector3d::Zero(), proxyV_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d device_ = Eigen::Vector3d::Zero(), server_ = Eigen::Vector3d::Zero();
    std::optional<double> lastFeedbackS_;
    double gain_ = 0, resumedAtS_ = -1e300, gainAtResume_ = 0;
    bool started_ = false;
};

// The safety gain alone, for tests: t since the last feedback (nullopt: never any) -> 0..1.
double silenceGain(const ForceModelParams& p, double sinceFeedbackS);

}  // namespace bop::haptic
