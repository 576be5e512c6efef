#pragma once
// spnav — a 3Dconnexion SpaceMouse or SpaceNavigator through spacenavd (Debian's libspnav): a
// six-axis controller held in place by springs, so its deflection sets the handle's velocity
// (rate control). It has no motors: forces are not felt (limits: 0 N), but the loop, the probe
// and the traces run as with any device.
#include "device/Device.hpp"

#include <memory>

namespace bop::haptic {

// `mmPerSPerUnit`: handle velocity per unit of deflection (spacenavd reports about -350..350).
// bop::Error when spacenavd cannot be reached, or when this build has no libspnav.
std::unique_ptr<Device> makeSpnavDevice(double mmPerSPerUnit, const DeviceLimits& limits);

}  // namespace bop::haptic
