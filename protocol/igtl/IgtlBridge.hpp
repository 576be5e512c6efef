#pragma once
// bop-igtl: a client of a served run (as the viewer is: the run's step never waits on it) that
// is an OpenIGTLink server (IgtlServer.hpp) for navigation tools. Out, in the scene's model
// space in mm as the receiver's RAS frame (docs/igtl.md): the bag's surface particles as POLYDATA
// "BoP surface" (normals and species as point data) and its volume particles as "BoP volume", at
// a stated rate; the probe as TRANSFORM "Probe" and its reaction force as POLYDATA "ProbeForce"
// (a line from the probe, its length the force times a scale); and to each client once, the
// scene's label map as IMAGE "BoP labels" (0 outside, else the bag's number). In, a TRANSFORM
// under the tool's device name moves BoP's probe to its translation (the tool tip), through the
// same checks as every probe; while none comes for a second, the probe lets go.
#include "IgtlServer.hpp"
#include "codec/Messages.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <string>

namespace bop::igtl {

struct BridgeOptions {
    std::string endpoint;                       // the served run, tcp://HOST:PORT
    ServerOptions igtl;                         // where OpenIGTLink clients connect
    double rateHz = 30;                         // bag updates per second, wall clock
    std::string tool = "StylusTipToReference";  // TRANSFORM device name that moves the probe
    double forceMmPerN = 10;                    // ProbeForce's length per newton, mm/N
    double k0 = 1, k1 = 1;                      // the probe's range scale and strength (paper eq. 9)
    std::chrono::milliseconds timeout{10000};   // connecting and downloading the map
    std::uint64_t maxMapBytes = std::uint64_t(1) << 30;
    double seconds = 0;  // stop after this long, wall clock s; 0: never
};

struct BridgeStats {
    std::uint64_t frames = 0;  // state frames turned into messages
    std::uint64_t probes = 0;  // probes sent from the tool's transforms
    ServerStats igtl;
};

// Runs until `stop` is set or opts.seconds have passed; `log` gets one line per event. Throws
// bop::Error when the run cannot be reached or its scene has no voxel grid (bulk material).
BridgeStats runBridge(const BridgeOptions& opts, const std::atomic<bool>& stop,
                      const std::function<void(const std::string&)>& log,
                      const std::function<void(int port)>& listening = {});

// Model mm of a simulation position, and back (SceneInfo's grid origin and unit system).
Eigen::Vector3d toMm(const protocol::SceneInfo& scene, const Eigen::Vector3d& sim);
Eigen::Vector3d fromMm(const protocol::SceneInfo& scene, const Eigen::Vector3d& mm);

}  // namespace bop::igtl
