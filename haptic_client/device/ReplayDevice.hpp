#pragma once
// replay:FILE — the probe track of a recorded session (bop-server --record, MCAP): the recorded
// probes' positions at their client times, played from the first, mapped into the device's
// millimetres by the workspace. Between recorded probes the position is interpolated linearly.
#include "device/Device.hpp"
#include "device/Workspace.hpp"

#include <memory>
#include <string>

namespace bop::haptic {

// bop::Error naming the file when it cannot be read or holds no probes.
std::unique_ptr<Device> makeReplayDevice(const std::string& path, const Workspace& workspace,
                                         const DeviceLimits& limits);

}  // namespace bop::haptic
