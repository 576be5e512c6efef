#pragma once
// Device to scene and back: scene = centre + scale * R * (device - deviceCentre), with
// `scale` scene length units per millimetre and R a rotation (identity by default); forces go
// the other way with `newtonsPerForce` (N per simulation force unit). Fitted by default so that
// the device's workspace spans the scene's box.
#include "bop/common/UnitSystem.hpp"
#include "device/Device.hpp"

#include <optional>

namespace bop::haptic {

struct Workspace {
    Eigen::Vector3d deviceCentreMm = Eigen::Vector3d::Zero();
    Eigen::Vector3d sceneCentre = Eigen::Vector3d::Zero();         // length
    double scale = 0.1;                                            // scene length per mm
    Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // device axes to scene axes
    double newtonsPerForce = 0.5;                                  // N per simulation force unit

    Eigen::Vector3d toScene(const Eigen::Vector3d& mm) const {
        return sceneCentre + scale * (rotation * (mm - deviceCentreMm));
    }
    Eigen::Vector3d toDevice(const Eigen::Vector3d& scene) const {
        return deviceCentreMm + rotation.conjugate() * ((scene - sceneCentre) / scale);
    }
    Eigen::Vector3d forceToDevice(const Eigen::Vector3d& f) const {
        return newtonsPerForce * (rotation.conjugate() * f);
    }
    Eigen::Vector3d forceToScene(const Eigen::Vector3d& n) const { return (rotation * n) / newtonsPerForce; }

    // The device's workspace box onto the scene's box: centres matched, and the smallest scale
    // at which the workspace reaches the whole box along every axis.
    static Workspace fit(const Eigen::AlignedBox3d& deviceMm, const Eigen::AlignedBox3d& scene, double newtonsPerForce);

    // The mapping a scene's units ask for (docs/haptics.md). With materials (units.physical) its
    // forces are newtons and its lengths millimetres: the device renders forceScale times the
    // tissue's N, and a device mm is a mm of tissue (centres matched); newtonsPerForce must then be
    // empty (std::invalid_argument). Without: fit(), at newtonsPerForce (default 0.5) x forceScale.
    static Workspace forScene(const Eigen::AlignedBox3d& deviceMm, const Eigen::AlignedBox3d& scene,
                              const UnitSystem& units, std::optional<double> newtonsPerForce, double forceScale);
};

}  // namespace bop::haptic
