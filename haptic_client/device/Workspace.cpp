#include "device/Workspace.hpp"

#include <stdexcept>
#include <string>

namespace bop::haptic {

Workspace Workspace::fit(const Eigen::AlignedBox3d& device, const Eigen::AlignedBox3d& scene, double newtonsPerForce) {
    Workspace w;
    w.deviceCentreMm = device.center();
    w.sceneCentre = scene.center();
    w.scale = (scene.sizes().array() / device.sizes().array().max(1e-9)).maxCoeff();
    w.newtonsPerForce = newtonsPerForce;
    return w;
}

Workspace Workspace::forScene(const Eigen::AlignedBox3d& device, const Eigen::AlignedBox3d& scene,
                              const UnitSystem& units, std::optional<double> newtonsPerForce, double forceScale) {
    if (units.physical && newtonsPerForce)
        throw std::invalid_argument("the scene's forces are in N (" + std::to_string(units.forceN()) +
                                    " N per simulation force unit); scale them with --force-scale");
    Workspace w = fit(device, scene, (units.physical ? units.forceN() : newtonsPerForce.value_or(0.5)) * forceScale);
    if (units.physical) w.scale = 1 / units.lengthMm;  // a mm on the device is a mm in the tissue
    return w;
}

}  // namespace bop::haptic
