#pragma once
// The valid range of every number a client sends (docs/protocol.md, "Valid ranges"). The decoders
// check the ranges that need nothing of the scene (Validate.cpp); the server's front checks the
// rest against its scene (server/InboundRanges.hpp). A value outside its range is refused with a
// reason and counted, never applied. The probe and parameter ranges are those of the viewer's
// sliders, widened a little: the dynamics stays stable at every corner of them.
#include <cstdint>

namespace bop::protocol::ranges {

// Any position a client sends (probe, seed): |x|, |y|, |z| at most this, length. The front then
// asks for the scene's box (InboundRanges.hpp); this bound keeps every later sum finite.
inline constexpr double kMaxCoordinate = 1e6;

// Probe (paper eq. 9), also as SetParameter "k0" / "k1".
inline constexpr double kMinProbeK0 = 0.1;  // range scale, dimensionless
inline constexpr double kMaxProbeK0 = 10;
inline constexpr double kMinProbeK1 = 0;  // strength, dimensionless
inline constexpr double kMaxProbeK1 = 50;

// SetParameter "lj", "co_normal", "co_planar": interspecies weights, dimensionless.
inline constexpr double kMaxWeight = 10;
// SetParameter "drag_v" (mass / time) and "drag_w" (inertia / time).
inline constexpr double kMaxDrag = 100;

// A haptic client's loop statistics, carried by its probes (display only).
inline constexpr float kMaxLoopRateHz = 100000;   // ticks per wall second
inline constexpr float kMaxPeriodErrorUs = 1e9f;  // microseconds
inline constexpr double kMaxRenderedForce = 1e6;  // |component| of the force a device rendered, force

// RunControl SingleStep: steps at a time.
inline constexpr std::uint32_t kMaxSingleSteps = 1000000;

}  // namespace bop::protocol::ranges
