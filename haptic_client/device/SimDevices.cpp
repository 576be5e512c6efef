#include "device/SimDevices.hpp"

#include <algorithm>
#include <cmath>

namespace bop::haptic {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Two unit vectors across `n`.
std::pair<Eigen::Vector3d, Eigen::Vector3d> across(const Eigen::Vector3d& n) {
    const Eigen::Vector3d a = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d u = n.cross(a).normalized();
    return {u, n.cross(u)};
}

// Seconds of the middle part: at depth, holding and then stroking or circling.
double middle(const PathScript& p) {
    switch (p.kind) {
        case PathKind::Poke:
            return p.holdS;
        case PathKind::Stroke:
            return p.holdS + 2 * p.lengthMm / p.speedMmPerS;
        case PathKind::Circle:
            return p.holdS + p.turns * 2 * kPi * p.radiusMm / p.speedMmPerS;
    }
    return 0;
}

class PathDevice final : public Device {
public:
    PathDevice(const PathScript& s, const DeviceLimits& l) : script_(s), limits_(l) {}
    std::string name() const override {
        return script_.kind == PathKind::Poke     ? "sim:poke"
               : script_.kind == PathKind::Stroke ? "sim:stroke"
                                                  : "sim:circle";
    }
    DeviceLimits limits() const override { return limits_; }
    DeviceState read(double t) override {
        DeviceState s;
        s.positionMm = pathAt(script_, t);
        s.finished = t >= pathDuration(script_);
        return s;
    }
    void render(const Eigen::Vector3d&, double) override {}  // a stiff arm: the force does not move it

private:
    PathScript script_;
    DeviceLimits limits_;
};

class FingerDevice final : public Device {
public:
    FingerDevice(const PathScript& s, const FingerParams& f, const DeviceLimits& l)
        : script_(s), finger_(f), limits_(l) {
        x_ = pathAt(s, 0);
    }
    std::string name() const override { return "sim:finger"; }
    DeviceLimits limits() const override { return limits_; }
    DeviceState read(double t) override {
        const double dt = std::clamp(t - t_, 0.0, 0.01);  // s; a stalled loop does not fling the finger
        t_ = t;
        // Semi-implicit Euler in mm, N, kg: a [mm/s^2] = 1000 * F [N] / m [kg].
        const double k = finger_.stiffnessNPerMm, m = finger_.massKg;
        const double c = 2 * finger_.dampingRatio * std::sqrt(k * 1000 * m) / 1000;  // N s / mm
        const Eigen::Vector3d f = k * (pathAt(script_, t) - x_) - c * v_ + force_;
        v_ += dt * 1000 * f / m;
        x_ += dt * v_;
        DeviceState s;
        s.positionMm = x_;
        s.finished = t >= pathDuration(script_);
        return s;
    }
    void render(const Eigen::Vector3d& forceN, double) override { force_ = forceN; }

private:
    PathScript script_;
    FingerParams finger_;
    DeviceLimits limits_;
    Eigen::Vector3d x_ = Eigen::Vector3d::Zero(), v_ = Eigen::Vector3d::Zero(), force_ = Eigen::Vector3d::Zero();
    double t_ = 0;
};

}  // namespace

double pathDuration(const PathScript& p) {
    return 2 * (p.standoffMm + p.depthMm) / p.speedMmPerS + middle(p);
}

Eigen::Vector3d pathAt(const PathScript& p, double t) {
    const Eigen::Vector3d n = p.inward.normalized();
    const double travel = (p.standoffMm + p.depthMm) / p.speedMmPerS;  // s, in or out
    const Eigen::Vector3d bottom = p.surfaceMm + p.depthMm * n;
    if (t <= travel) return p.surfaceMm + (-p.standoffMm + p.speedMmPerS * std::max(t, 0.0)) * n;
    const double mid = middle(p);
    if (t >= travel + mid) return bottom - p.speedMmPerS * std::min(t - travel - mid, travel) * n;
    const double u = t - travel - p.holdS;  // s into the stroke or circle
    if (u <= 0 || p.kind == PathKind::Poke) return bottom;
    const auto [a, b] = across(n);
    if (p.kind == PathKind::Stroke) {
        const double s = p.speedMmPerS * u;  // there and back
        return bottom + (s <= p.lengthMm ? s : 2 * p.lengthMm - s) * a;
    }
    const double theta = p.speedMmPerS * u / p.radiusMm;
    return bottom + p.radiusMm * ((std::cos(theta) - 1) * a + std::sin(theta) * b);
}

std::unique_ptr<Device> makePathDevice(const PathScript& s, const DeviceLimits& l) {
    return std::make_unique<PathDevice>(s, l);
}

std::unique_ptr<Device> makeFingerDevice(const PathScript& s, const FingerParams& f, const DeviceLimits& l) {
    return std::make_unique<FingerDevice>(s, f, l);
}

}  // namespace bop::haptic
