#include "recording/FoxgloveChannels.hpp"

#include "recording/FoxgloveMessages.hpp"
#include "recording/SessionTopics.hpp"

#include <span>

namespace bop::protocol {
namespace embedded {
extern const std::uint8_t pointCloudSchema[], sceneUpdateSchema[], frameTransformSchema[], frameStatsSchema[];
extern const std::size_t pointCloudSchemaSize, sceneUpdateSchemaSize, frameTransformSchemaSize, frameStatsSchemaSize;
}  // namespace embedded

FoxgloveChannels::FoxgloveChannels(recording::McapWriter& w, SceneInfo scene) : w_(w), scene_(std::move(scene)) {
    using namespace embedded;
    const auto schema = [&](const char* name, const std::uint8_t* data, std::size_t size) {
        return w_.addSchema(name, "flatbuffer", std::span<const std::uint8_t>(data, size));
    };
    const std::uint16_t cloud = schema("foxglove.PointCloud", pointCloudSchema, pointCloudSchemaSize);
    const std::uint16_t update = schema("foxglove.SceneUpdate", sceneUpdateSchema, sceneUpdateSchemaSize);
    const std::uint16_t transform = schema("foxglove.FrameTransform", frameTransformSchema, frameTransformSchemaSize);
    const std::uint16_t stats = schema("bop.plot.FrameStats", frameStatsSchema, frameStatsSchemaSize);
    stats_ = w_.addChannel(stats, kTopicStats, "flatbuffer");
    particles_ = w_.addChannel(cloud, kTopicParticles, "flatbuffer");
    surfels_ = w_.addChannel(update, kTopicSurfels, "flatbuffer");
    probe_ = w_.addChannel(update, kTopicProbeShape, "flatbuffer");
    transform_ = w_.addChannel(transform, kTopicTransform, "flatbuffer");
}

bool FoxgloveChannels::derived(const std::string& topic) {
    for (const char* t : {kTopicStats, kTopicParticles, kTopicSurfels, kTopicProbeShape, kTopicTransform})
        if (topic == t) return true;
    return false;
}

void FoxgloveChannels::write(std::uint16_t channel, const Buffer& b, std::uint64_t timeNs) {
    w_.write(channel, sequence_[channel]++, timeNs, timeNs, b);
}

void FoxgloveChannels::frameChunk(const Buffer& chunk, std::uint64_t logTimeNs) {
    FrameLimits limits;
    limits.maxChunkBytes = kAbsoluteMaxBytes;
    auto d = decodeStateFrame(chunk.data(), chunk.size(), limits);
    if (d) frameChunk(std::move(d.value), logTimeNs);
}

void FoxgloveChannels::frameChunk(const StateFrame& chunk, std::uint64_t logTimeNs) {
    const auto frame = assembler_.add(chunk);
    if (!frame) return;
    write(transform_, fox::worldToBop(scene_, logTimeNs), logTimeNs);
    write(stats_, fox::frameStats(*frame, scene_, logTimeNs), logTimeNs);
    write(particles_, fox::pointCloud(*frame, scene_, logTimeNs), logTimeNs);
    write(surfels_, fox::surfels(*frame, scene_, logTimeNs), logTimeNs);
    write(probe_, fox::probe(*frame, scene_, logTimeNs), logTimeNs);
    ++frames_;
}

}  // namespace bop::protocol
