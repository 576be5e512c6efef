#pragma once
// Devices by name (bop-haptic --device): sim:poke, sim:stroke, sim:circle, sim:finger,
// replay:FILE, spnav. The scripted paths are given in scene units (where the bag is) and
// turned into device millimetres by the workspace.
#include "device/Device.hpp"
#include "device/SimDevices.hpp"
#include "device/Workspace.hpp"

#include <memory>
#include <string>

namespace bop::haptic {

struct DeviceOptions {
    Eigen::Vector3d target = Eigen::Vector3d::Zero();    // the surface point, length
    Eigen::Vector3d inward = -Eigen::Vector3d::UnitZ();  // into the object
    double standoff = 4;                                 // start this far outside, length
    double depth = 2;                                    // go this far in, length
    double speed = 1;                                    // length / s
    double holdS = 1;                                    // s at depth
    double strokeLength = 6;                             // length
    double circleRadius = 2;                             // length
    double turns = 1;
    FingerParams finger;
    double spnavGain = 0.2;  // mm/s per unit of deflection
};

// bop::Error naming the spec when it is not one of the above, or the device cannot be opened.
std::unique_ptr<Device> makeDevice(const std::string& spec, const DeviceOptions& options, const Workspace& workspace,
                                   const DeviceLimits& limits);

}  // namespace bop::haptic
