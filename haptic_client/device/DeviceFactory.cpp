#include "device/DeviceFactory.hpp"

#include "bop/common/Error.hpp"
#include "device/ReplayDevice.hpp"
#include "device/SpnavDevice.hpp"

namespace bop::haptic {

std::unique_ptr<Device> makeDevice(const std::string& spec, const DeviceOptions& o, const Workspace& w,
                                   const DeviceLimits& limits) {
    PathScript p;
    p.surfaceMm = w.toDevice(o.target);
    p.inward = w.rotation.conjugate() * o.inward.normalized();
    p.standoffMm = o.standoff / w.scale;
    p.depthMm = o.depth / w.scale;
    p.speedMmPerS = o.speed / w.scale;
    p.holdS = o.holdS;
    p.lengthMm = o.strokeLength / w.scale;
    p.radiusMm = o.circleRadius / w.scale;
    p.turns = o.turns;
    if (spec == "sim:poke") return makePathDevice(p, limits);
    if (spec == "sim:stroke") return p.kind = PathKind::Stroke, makePathDevice(p, limits);
    if (spec == "sim:circle") return p.kind = PathKind::Circle, makePathDevice(p, limits);
    if (spec == "sim:finger") return makeFingerDevice(p, o.finger, limits);
    if (spec.rfind("replay:", 0) == 0) return makeReplayDevice(spec.substr(7), w, limits);
    if (spec == "spnav") return makeSpnavDevice(o.spnavGain, limits);
    throw Error("--device", "unknown device '" + spec +
                                "'; expected sim:poke, sim:stroke, sim:circle, sim:finger, "
                                "replay:FILE or spnav");
}

}  // namespace bop::haptic
