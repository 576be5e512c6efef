#pragma once
// A haptic device as the 1 kHz loop sees it (docs/haptics.md): read once per tick, given a force
// once per tick. Device units: millimetres, newtons, seconds since the loop started. Scene
// coordinates come from the workspace mapping (Workspace.hpp).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <string>

namespace bop::haptic {

struct DeviceLimits {
    Eigen::AlignedBox3d workspaceMm{Eigen::Vector3d::Constant(-80), Eigen::Vector3d::Constant(80)};  // reach, mm
    double maxForceN = 3.3;           // the most it renders continuously, N (0: no force output)
    double maxStiffnessNPerMm = 1.0;  // the stiffest spring it renders stably, N/mm
};

struct DeviceState {
    Eigen::Vector3d positionMm = Eigen::Vector3d::Zero();
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    std::uint32_t buttons = 0;  // bit k: button k pressed
    bool finished = false;      // a scripted or replayed device has nothing more to do
};

class Device {
public:
    virtual ~Device() = default;
    virtual std::string name() const = 0;
    virtual DeviceLimits limits() const = 0;
    virtual DeviceState read(double tS) = 0;
    // The force the user feels from now to the next tick, N (already clamped by the caller).
    virtual void render(const Eigen::Vector3d& forceN, double tS) = 0;
};

}  // namespace bop::haptic
