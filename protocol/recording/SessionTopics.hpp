#pragma once
// The channel topics of a recorded session (docs/protocol.md "Recording and replay"): what
// SessionRecorder writes and SessionReader reads, one message type each.
namespace bop::protocol {

inline constexpr const char* kTopicScene = "/bop/scene";                 // SceneInfo
inline constexpr const char* kTopicCommand = "/bop/command";             // Command
inline constexpr const char* kTopicReply = "/bop/reply";                 // CommandReply
inline constexpr const char* kTopicProbe = "/bop/probe";                 // Probe
inline constexpr const char* kTopicProbeApplied = "/bop/probe_applied";  // Feedback: the step it was applied at
inline constexpr const char* kTopicFrame = "/bop/frame";                 // StateFrame chunk

}  // namespace bop::protocol
