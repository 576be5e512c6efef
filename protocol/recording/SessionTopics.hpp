#pragma once
// The channel topics of a recorded session (docs/protocol.md "Recording and replay"): what
// SessionRecorder writes and SessionReader reads, one message type each; then what
// FoxgloveChannels derives from the frames for Foxglove's panels (bop-replay export rewrites them).
namespace bop::protocol {

inline constexpr const char* kTopicScene = "/bop/scene";                 // SceneInfo
inline constexpr const char* kTopicCommand = "/bop/command";             // Command
inline constexpr const char* kTopicReply = "/bop/reply";                 // CommandReply
inline constexpr const char* kTopicProbe = "/bop/probe";                 // Probe
inline constexpr const char* kTopicProbeApplied = "/bop/probe_applied";  // Feedback: the step it was applied at
inline constexpr const char* kTopicFrame = "/bop/frame";                 // StateFrame chunk

inline constexpr const char* kTopicStats = "/bop/stats";                // bop.plot.FrameStats, one per frame
inline constexpr const char* kTopicParticles = "/foxglove/particles";   // foxglove.PointCloud
inline constexpr const char* kTopicSurfels = "/foxglove/surfels";       // foxglove.SceneUpdate: discs
inline constexpr const char* kTopicProbeShape = "/foxglove/probe";      // foxglove.SceneUpdate: sphere, arrow
inline constexpr const char* kTopicTransform = "/foxglove/transforms";  // foxglove.FrameTransform

}  // namespace bop::protocol
