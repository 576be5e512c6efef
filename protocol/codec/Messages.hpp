#pragma once
// Plain C++ forms of the wire messages (schemas/*.fbs), free of FlatBuffers types. Units, unless
// a comment says otherwise: length in simulation units (LJ equilibrium spacing r0 = sqrt 3), time
// in simulation time units, force in simulation force units, energy = force x length; "Mm" is
// millimetres of the shape model, "Ns" nanoseconds of a steady wall clock, "Hz" per wall second.
// Species are numbered from 1 as in the scene file; 0 is never a species.
#include "bop/common/UnitSystem.hpp"
#include "codec/ProtocolVersion.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace bop::protocol {

// ---- handshake ----

enum class Role : std::uint8_t { Viewer = 0, Haptic = 1, Replay = 2, Control = 3 };

struct Hello {
    std::uint16_t protocolVersion = kProtocolVersion;  // sender's version, >= 1
    Role role = Role::Viewer;
    float frameRateHz = 0;           // wanted state-frame rate, wall Hz; 0 = the server's default
    bool readOnly = false;           // asks for a session that may not send commands
    std::string clientName;          // for logs, at most kMaxNameBytes
    std::uint16_t udpFramePort = 0;  // the client's UDP port for frames as datagrams; 0 = none
};

enum class SpeciesKind : std::uint8_t { Surface = 0, Volume = 1 };

struct SpeciesInfo {
    std::string name;  // at most kMaxNameBytes
    SpeciesKind kind = SpeciesKind::Surface;
    std::array<std::uint8_t, 4> rgba{255, 255, 255, 255};  // display colour, straight alpha
};

struct Endpoints {
    std::string frameEndpoint;       // ZeroMQ endpoint of the state-frame PUB socket
    std::uint16_t udpFramePort = 0;  // 0 = none
    std::uint16_t udpProbePort = 0;  // 0 = none
};

// The values a viewer's sliders start from (scene.fbs Tunables). Matrices are n x n row-major
// over the n species, row a = the receiving species; all empty when the server did not send them,
// and sent only for at most kMaxTunedSpecies species (so that SceneInfo stays within its cap).
inline constexpr std::size_t kMaxTunedSpecies = 16;
struct Tunables {
    std::vector<double> lj, coNormal, coPlanar;  // interspecies weights, dimensionless
    std::vector<double> dragV;                   // per species, mass / time
    std::vector<double> dragW;                   // per species, inertia / time
    double k0 = 1, k1 = 1;                       // probe (paper eq. 9), dimensionless
};

struct SceneInfo {
    std::uint16_t protocolVersion = kProtocolVersion;
    std::vector<SpeciesInfo> species;                 // entry k describes species k + 1; at most 255
    Eigen::Vector3d boxLo = Eigen::Vector3d::Zero();  // simulation box, length
    Eigen::Vector3d boxHi = Eigen::Vector3d::Ones();
    Eigen::Vector3d gridOriginMm = Eigen::Vector3d::Zero();  // corner of voxel (0,0,0), mm
    std::array<std::int32_t, 3> gridDims{0, 0, 0};           // voxels per axis; all 0 = no gradient map
    double voxelSizeMm = 1.0;                                // voxel edge, mm
    double r0 = 1.7320508075688772;                          // LJ equilibrium spacing, length
    double r0Voxels = 0;                                     // r0 in voxels (0 when there is no map)
    double dt = 0.001;                                       // integration step, time
    Endpoints endpoints;
    std::uint64_t particleCount = 0;  // at the time of the handshake
    std::string units;                // the units in words, at most kMaxTextBytes
    float publishRateHz = 0;          // the server's state-frame rate, wall Hz (0 = not sent)
    double probeReach = 0;            // the probe's reach at k0 = 1 (LJ cutoff), length; scales with k0; 0 = not sent
    Tunables tunables;
    std::uint64_t mapBytes = 0;  // the gradient-map file a client may download (MapRequest); 0 = none
    std::uint64_t mapKey = 0;    // the key that file was made for (GradientMapFile.hpp)
    float sessionTimeoutS = 0;   // a session silent this long is forgotten, s; 0 = never (older servers)
    // What a simulation unit is in mm, kg and s (docs/physics.md §8); older servers: not known.
    bop::UnitSystem unitSystem;
};

// ---- state frames ----

enum class FrameEncoding : std::uint8_t {
    Float32 = 0,      // 12 bytes per position, 12 per normal
    Quantised16 = 1,  // 6 bytes per position (uint16 against quantLo/Hi), 4 per normal (octahedral)
    Compact8 = 2,     // 6 bytes per position as Quantised16, 2 per normal (octahedral, 8-bit), species
                      // as runs (a chunk's particles grouped by species); decoded in that order
};

// A haptic client's device loop as it measures itself; all 0 when there is none.
struct LoopStats {
    float rateHz = 0;                   // ticks per second
    float periodErrorP99Us = 0;         // 99th percentile of |tick - deadline|, microseconds
    std::uint64_t missedDeadlines = 0;  // since the start: ticks a period or more late, deadlines skipped
};

struct FrameStats {
    double kinetic = 0;               // whole system, energy
    double potential = 0;             // whole system, energy
    double pressure = 0;              // virial pressure (of the blood, volume particles, in a bag), energy / length^3
    double stepRateHz = 0;            // steps per wall second
    std::uint64_t particleCount = 0;  // particles in the simulation
    LoopStats haptic;                 // of the haptic client probing now (from its probes)
    double cavityVolume = 0;          // the bag(s) in the map(s) in force, length^3 (0: no map)
    double mapFrame = 0;              // keyframe in force plus its blend towards the next
    double realTimeFactor = 0;        // simulated s per wall s (physical units); 0: time in simulation units
};

// One chunk of a state frame (a whole frame is one chunk with chunkCount 1). The particle arrays
// always hold float32 here; `encoding` says how they travel. count() = species.size().
struct StateFrame {
    std::uint64_t frameSeq = 0;
    std::uint32_t chunkIndex = 0;  // < chunkCount
    std::uint32_t chunkCount = 1;
    std::uint64_t step = 0;
    double simTime = 0;  // time
    std::int64_t serverTimeNs = 0;
    Eigen::Vector3d probePosition = Eigen::Vector3d::Zero();  // length
    Eigen::Vector3d probeForce = Eigen::Vector3d::Zero();     // reaction on the probe, force
    bool probeActive = false;
    FrameStats stats;
    std::uint32_t frameParticleCount = 0;  // particles in the whole frame (all chunks)
    std::uint32_t firstIndex = 0;          // frame index of this chunk's first particle
    FrameEncoding encoding = FrameEncoding::Float32;
    Eigen::Vector3d quantLo = Eigen::Vector3d::Zero();  // Quantised16 bounds, length (the scene box)
    Eigen::Vector3d quantHi = Eigen::Vector3d::Ones();
    std::vector<float> positions;       // 3 per particle, length
    std::vector<float> normals;         // 3 per particle (unit), or empty
    std::vector<std::uint8_t> species;  // 1 per particle
    std::vector<std::uint64_t> ids;     // 1 per particle, or empty

    std::size_t count() const { return species.size(); }
};

// ---- haptics ----

struct Probe {
    std::uint64_t seq = 0;
    std::int64_t clientTimeNs = 0;
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // length
    bool active = false;
    double k0 = 1.0;                                          // range scale of paper eq. 9, dimensionless, > 0
    double k1 = 1.0;                                          // strength of paper eq. 9, dimensionless
    LoopStats loop;                                           // the sender's device loop (haptic clients)
    Eigen::Vector3d renderedForce = Eigen::Vector3d::Zero();  // what its device rendered at this tick, force
};

struct Feedback {
    std::uint64_t probeSeq = 0;  // newest probe applied at this step
    std::uint64_t step = 0;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();  // reaction on the probe, force
    std::int64_t serverTimeNs = 0;
    std::uint32_t mapEdits = 0;  // edits of the gradient map the server has made so far (MapEdits)
};

// ---- the gradient map, for haptic clients ----

struct MapRequest {
    std::uint64_t offset = 0;  // first byte wanted
    std::uint32_t length = 0;  // bytes wanted, 1 .. kMaxMapPieceBytes
};

struct MapChunk {
    std::uint64_t offset = 0;        // where data starts in the file
    std::uint64_t total = 0;         // the file's size; 0 = the server has no map
    std::vector<std::uint8_t> data;  // at most kMaxMapPieceBytes, within [0, total)
};

// ---- refusals ----

// One of the client's messages refused and not applied (schemas/refusal.fbs).
struct Refusal {
    std::string kind;           // the refused message's kind ("Probe", ...), at most kMaxNameBytes
    std::uint64_t seq = 0;      // its sequence (Probe) or request id (Command); 0 when unreadable
    std::string reason;         // "<Message>.<field>: <problem>", at most kMaxTextBytes
    std::uint64_t refused = 0;  // refusals of the session (UDP: of the address) so far
};

// ---- commands ----

struct SeedParticle {
    int species = 1;                                     // 1..255
    Eigen::Vector3d position = Eigen::Vector3d::Zero();  // length
};
struct SetBirth {
    int species = 1;  // 1..255
    bool enabled = true;
};
// Names and units of the value are listed in schemas/command.fbs ("lj", "k0", "drag_v", ...).
struct SetParameter {
    std::string name;  // 1..kMaxNameBytes bytes
    int speciesA = 0;  // 0 = not species-specific
    int speciesB = 0;  // 0 = none
    double value = 0;
};
enum class RunAction : std::uint8_t { Pause = 0, Resume = 1, SingleStep = 2 };
struct RunControl {
    RunAction action = RunAction::Pause;
    std::uint32_t steps = 1;  // SingleStep: >= 1
};
struct SwitchMapFrame {
    std::uint32_t frame = 0;  // 0-based frame of a 4D gradient map
};
struct Checkpoint {
    std::string path;  // on the server; empty = default name
};
struct Record {
    bool start = true;  // false = stop
    std::string path;   // on the server; empty = default name
};

// A blade of `radius` swept from `from` to `to` (schemas/command.fbs).
struct Cut {
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();  // length
    double radius = 0;                                                             // length, > 0
};

// ---- the gradient map's edits, for haptic clients whose copy follows the server's ----

struct MapEditsRequest {
    std::uint32_t first = 0;  // the first edit wanted, 0-based
};

// A blade (cut.radius > 0, voxels empty) or voxels that left their bags (cut.radius 0).
struct MapEdit {
    Cut cut;
    std::vector<std::uint64_t> voxels;  // whole-map indices, x fastest, increasing, 1..kMaxEditVoxels of them
};

struct MapEdits {
    std::uint32_t first = 0;  // the number of edits[0]
    std::uint32_t total = 0;  // the edits the server has made so far, >= first + edits.size()
    std::vector<MapEdit> edits;
};

using CommandBody =
    std::variant<SeedParticle, SetBirth, SetParameter, RunControl, SwitchMapFrame, Checkpoint, Record, Cut>;

struct Command {
    std::uint64_t requestId = 0;  // echoed in the reply
    CommandBody body;
};

enum class ReplyStatus : std::uint8_t { Ok = 0, Rejected = 1, Unsupported = 2, ReadOnly = 3, Failed = 4 };

struct CommandReply {
    std::uint64_t requestId = 0;
    ReplyStatus status = ReplyStatus::Ok;
    std::uint64_t step = 0;  // step at which the command takes effect
    std::string message;     // at most kMaxTextBytes
};

}  // namespace bop::protocol
