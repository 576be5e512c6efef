#pragma once
// A served session recorded as MCAP (docs/protocol.md "Recording"): the scene, every command
// with the reply that says the step at which it was applied, every probe with the step at
// which it was applied (a Feedback message: probe sequence and step), and every state-frame
// chunk sent, each on its own channel with the binary FlatBuffers schema embedded, so MCAP
// tools can open it; beside them, for every whole frame, the channels Foxglove shows in its 3D and
// Plot panels (FoxgloveChannels.hpp). Chunked, indexed and zstd-compressed (McapWriter.hpp).
// Timestamps are wall-clock nanoseconds since the Unix epoch.
// One thread (the front's) owns a recorder.
#include "codec/Codec.hpp"
#include "recording/FoxgloveChannels.hpp"
#include "recording/McapWriter.hpp"
#include "recording/SessionTopics.hpp"

#include <map>
#include <memory>
#include <string>

namespace bop::protocol {

class SessionRecorder {
public:
    // bop::Error naming the file if it cannot be created. `meta` goes into the scene channel's
    // metadata (scene file, ranks, server options).
    SessionRecorder(const std::string& path, const SceneInfo& scene, const std::map<std::string, std::string>& meta);
    void command(const Buffer& command, const Buffer& reply);
    void probe(const Buffer& probe, const Buffer& applied);  // applied: Feedback with the probe's seq and step
    void frameChunk(const Buffer& chunk);
    void close();  // finishes the file (also done by the destructor's owner at shutdown)
    const std::string& path() const { return writer_.path(); }

private:
    void write(std::uint16_t channel, const Buffer& b);
    recording::McapWriter writer_;
    std::uint16_t scene_ = 0, command_ = 0, reply_ = 0, probe_ = 0, applied_ = 0, frame_ = 0;
    std::map<std::uint16_t, std::uint32_t> sequence_;
    FoxgloveChannels foxglove_;
};

}  // namespace bop::protocol
