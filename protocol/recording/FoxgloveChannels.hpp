#pragma once
// The channels a recording adds for Foxglove beside the wire messages (FoxgloveMessages.hpp):
// for every whole state frame, a point cloud of the particles, the surfels as discs, the probe,
// the world-to-bop transform and a row of plottable numbers, each on its own topic
// (SessionTopics.hpp) with its binary FlatBuffers schema in the file. Used by SessionRecorder as
// it records and by `bop-replay export` on recordings made without them.
#include "client/FrameAssembler.hpp"
#include "codec/Codec.hpp"
#include "recording/McapWriter.hpp"

#include <cstdint>
#include <map>
#include <string>

namespace bop::protocol {

class FoxgloveChannels {
public:
    // Adds the schemas and channels to w (which must outlive this object).
    FoxgloveChannels(recording::McapWriter& w, SceneInfo scene);
    // Takes one frame chunk as sent (trusted: the server's own, or a recording's that decoded);
    // when it completes its frame, writes that frame's messages at logTimeNs.
    void frameChunk(const StateFrame& chunk, std::uint64_t logTimeNs);
    void frameChunk(const Buffer& chunk, std::uint64_t logTimeNs);  // decodes it first; skips one that does not decode
    std::uint64_t framesWritten() const { return frames_; }

    // True for the topics these channels write (a recording's copy of them is rewritten, not kept).
    static bool derived(const std::string& topic);

private:
    void write(std::uint16_t channel, const Buffer& b, std::uint64_t timeNs);
    recording::McapWriter& w_;
    SceneInfo scene_;
    FrameAssembler assembler_;
    std::uint16_t stats_ = 0, particles_ = 0, surfels_ = 0, probe_ = 0, transform_ = 0;
    std::map<std::uint16_t, std::uint32_t> sequence_;
    std::uint64_t frames_ = 0;
};

}  // namespace bop::protocol
