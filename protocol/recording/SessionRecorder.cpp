#include "recording/SessionRecorder.hpp"

#include <chrono>
#include <cstddef>
#include <span>

namespace bop::protocol {
namespace embedded {
extern const std::uint8_t sceneSchema[], commandSchema[], replySchema[], probeSchema[], feedbackSchema[], frameSchema[];
extern const std::size_t sceneSchemaSize, commandSchemaSize, replySchemaSize, probeSchemaSize, feedbackSchemaSize,
    frameSchemaSize;
}  // namespace embedded

namespace {

std::uint64_t wallNs() {
    return std::uint64_t(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count());
}

}  // namespace

SessionRecorder::SessionRecorder(const std::string& path, const SceneInfo& scene,
                                 const std::map<std::string, std::string>& meta)
    : writer_(path), foxglove_(writer_, scene) {
    using namespace embedded;
    const auto channel = [&](const char* topic, const char* root, const std::uint8_t* schema, std::size_t size,
                             const std::map<std::string, std::string>& m = {}) {
        const std::uint16_t id = writer_.addSchema(root, "flatbuffer", std::span<const std::uint8_t>(schema, size));
        return writer_.addChannel(id, topic, "flatbuffer", m);
    };
    scene_ = channel(kTopicScene, "bop.wire.SceneInfo", sceneSchema, sceneSchemaSize, meta);
    command_ = channel(kTopicCommand, "bop.wire.Command", commandSchema, commandSchemaSize);
    reply_ = channel(kTopicReply, "bop.wire.CommandReply", replySchema, replySchemaSize);
    probe_ = channel(kTopicProbe, "bop.wire.Probe", probeSchema, probeSchemaSize);
    applied_ = channel(kTopicProbeApplied, "bop.wire.Feedback", feedbackSchema, feedbackSchemaSize);
    frame_ = channel(kTopicFrame, "bop.wire.StateFrame", frameSchema, frameSchemaSize);
    write(scene_, encodeSceneInfo(scene));
}

void SessionRecorder::write(std::uint16_t channel, const Buffer& b) {
    const std::uint64_t t = wallNs();
    writer_.write(channel, sequence_[channel]++, t, t, b);
}

void SessionRecorder::command(const Buffer& command, const Buffer& reply) {
    write(command_, command);
    write(reply_, reply);
}

void SessionRecorder::probe(const Buffer& probe, const Buffer& applied) {
    write(probe_, probe);
    write(applied_, applied);
}

void SessionRecorder::frameChunk(const Buffer& chunk) {
    const std::uint64_t t = wallNs();
    writer_.write(frame_, sequence_[frame_]++, t, t, chunk);
    foxglove_.frameChunk(chunk, t);
}

void SessionRecorder::close() {
    writer_.close();
}

}  // namespace bop::protocol
