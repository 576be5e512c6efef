#pragma once
// Simulated devices (docs/haptics.md), in device millimetres:
//  - sim:poke    the handle approaches a surface point along `inward` from `standoff` outside,
//                goes `depth` in at `speed`, holds, and comes back out;
//  - sim:stroke  the same approach, then a stroke of `length` along the surface and back;
//  - sim:circle  the same approach, then `turns` circles of `radius` in the surface's plane;
// all three follow their path whatever the force (a stiff arm, not a hand); and
//  - sim:finger  a fingertip: a mass on a spring and damper pulled toward the poke path and
//                pushed back by the force it is given, so feedback changes its motion.
#include "device/Device.hpp"

#include <memory>

namespace bop::haptic {

enum class PathKind { Poke, Stroke, Circle };

struct PathScript {
    PathKind kind = PathKind::Poke;
    Eigen::Vector3d surfaceMm = Eigen::Vector3d::Zero();  // the point on the surface
    Eigen::Vector3d inward = -Eigen::Vector3d::UnitZ();   // into the object (normalised on use)
    double standoffMm = 10;                               // start this far outside
    double depthMm = 5;                                   // go this far in
    double speedMmPerS = 10;
    double holdS = 1;      // at depth before stroking, circling or coming out
    double lengthMm = 20;  // stroke
    double radiusMm = 5;   // circle
    double turns = 1;      // circle
};

// Where the path is at time t (mm), and whether it has ended.
Eigen::Vector3d pathAt(const PathScript& p, double tS);
double pathDuration(const PathScript& p);

// Mass-spring-damper fingertip: m x'' = k (target - x) - c x' + F. Defaults: a 50 g fingertip on
// a 0.2 N/mm spring, damping ratio 0.7.
struct FingerParams {
    double massKg = 0.05;
    double stiffnessNPerMm = 0.2;
    double dampingRatio = 0.7;
};

std::unique_ptr<Device> makePathDevice(const PathScript& script, const DeviceLimits& limits);
std::unique_ptr<Device> makeFingerDevice(const PathScript& script, const FingerParams& finger,
                                         const DeviceLimits& limits);

}  // namespace bop::haptic
