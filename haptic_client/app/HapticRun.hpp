#pragma once
// bop-haptic's two runs: against a server (runHaptic) and the device loop alone (runLoopOnly,
// for its timing). Both print a summary (loop rate, period error, missed deadlines, round trip)
// and write haptic-trace.csv; a poke also writes its stiffness curve.
#include "control/ForceModel.hpp"
#include "device/DeviceFactory.hpp"

#include <optional>
#include <string>

namespace bop::haptic {

struct RunOptions {
    std::string endpoint;
    std::string device = "sim:poke";
    bool loopOnly = false;
    double seconds = 0;  // 0: until the device's script ends (loop only: 10 s)
    double rateHz = 1000;
    std::string outDir = "out/haptic";
    std::optional<Eigen::Vector3d> target;  // scripted devices' surface point; default: the top of the bag
    DeviceOptions script;
    ForceModelParams model;
    double fieldStiffness = 5;  // force / length; 0: no field
    // Whether --stiffness and --field-stiffness were given: for a scene with materials the coupling
    // defaults to the device's stiffest and the field to none, so the hand feels the tissue's N/mm.
    bool couplingGiven = false, fieldGiven = false;
    DeviceLimits limits;
    // N per simulation force unit for a scene without materials (default 0.5); a scene with them
    // gives its forces in N (SceneInfo's units) and refuses this.
    std::optional<double> newtonsPerForce;
    double forceScale = 1;                           // the scene's N times this on the device (a stated scale-down)
    double workspaceScale = 0;                       // length per mm; 0: the device's workspace spans the scene's box
    std::optional<Eigen::Vector3d> workspaceCentre;  // the scene point at the workspace's centre; default: the box's
    double k0 = 0, k1 = 0;                           // 0: the server's
    // Cutting: always (--cut) or while a device button is held (--cut-button; -1: none); the
    // blade's radius, length.
    bool cut = false;
    int cutButton = -1;
    double cutRadius = 1.7320508075688772;  // r0
    bool udp = false;
    double mapMaxMb = 512;
    double reconnectAfterS = 2;                  // no feedback for this long: connect again (0: never)
    std::string serverKeyFile, clientKeyPrefix;  // CURVE: the server's public key file, this client's pair prefix
};

int runHaptic(const RunOptions& options);
int runLoopOnly(const RunOptions& options);

}  // namespace bop::haptic
