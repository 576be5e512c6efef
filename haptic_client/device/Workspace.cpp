#include "device/Workspace.hpp"

namespace bop::haptic {

Workspace Workspace::fit(const Eigen::AlignedBox3d& device, const Eigen::AlignedBox3d& scene, double newtonsPerForce) {
    Workspace w;
    w.deviceCentreMm = device.center();
    w.sceneCentre = scene.center();
    w.scale = (scene.sizes().array() / device.sizes().array().max(1e-9)).maxCoeff();
    w.newtonsPerForce = newtonsPerForce;
    return w;
}

}  // namespace bop::haptic
