#include "recording/RecordingExport.hpp"

#include "bop/common/Error.hpp"
#include "recording/FoxgloveChannels.hpp"
#include "recording/McapReader.hpp"
#include "recording/SessionTopics.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>

namespace bop::protocol {

ExportReport exportRecording(const std::string& in, const std::string& out,
                             const recording::McapWriterOptions& options) {
    using namespace recording;
    const bool partial = in.size() > 8 && in.ends_with(".partial");
    const McapFile f = readMcap(in, partial ? McapReadMode::Tolerant : McapReadMode::Strict);
    const McapChannel* frames = nullptr;
    const McapChannel* scene = nullptr;
    for (const auto& c : f.channels) {
        if (c.topic == kTopicFrame) frames = &c;
        if (c.topic == kTopicScene) scene = &c;
    }
    if (!scene) throw Error(in, "no " + std::string(kTopicScene) + " channel: not a BoP session recording");
    std::optional<SceneInfo> sceneInfo;
    for (const auto& m : f.messages) {
        if (m.channelId != scene->id) continue;
        auto d = decodeSceneInfo(m.data.data(), m.data.size());
        if (!d) throw Error(in, "its scene message does not decode: " + d.message);
        sceneInfo = std::move(d.value);
        break;
    }
    if (!sceneInfo) throw Error(in, "no scene message: not a BoP session recording");
    if (std::filesystem::exists(out) && std::filesystem::equivalent(in, out))
        throw Error(out, "is the input; export writes a new file");

    ExportReport r;
    r.inputBytes = std::filesystem::file_size(in);
    McapWriter w(out, f.profile, options);
    std::map<std::uint16_t, std::uint16_t> schemaId, channelId;  // input id -> output id
    for (const auto& c : f.channels) {
        if (FoxgloveChannels::derived(c.topic)) continue;
        if (c.schemaId != 0 && !schemaId.count(c.schemaId)) {
            const McapSchema& s = *f.schema(c.schemaId);
            schemaId[c.schemaId] = w.addSchema(s.name, s.encoding, s.data);
        }
        channelId[c.id] =
            w.addChannel(c.schemaId == 0 ? 0 : schemaId.at(c.schemaId), c.topic, c.messageEncoding, c.metadata);
    }
    FoxgloveChannels foxglove(w, *sceneInfo);
    std::uint64_t first = ~std::uint64_t(0), last = 0;
    for (const auto& m : f.messages) {
        first = std::min(first, m.logTimeNs);
        last = std::max(last, m.logTimeNs);
        const auto it = channelId.find(m.channelId);
        if (it == channelId.end()) continue;
        w.write(it->second, m.sequence, m.logTimeNs, m.publishTimeNs, m.data);
        ++r.messagesCopied;
        if (frames && m.channelId == frames->id) foxglove.frameChunk(m.data, m.logTimeNs);
    }
    w.close();
    r.framesDerived = foxglove.framesWritten();
    r.chunks = w.chunkCount();
    r.outputBytes = std::filesystem::file_size(out);
    if (last > first) r.seconds = double(last - first) * 1e-9;
    return r;
}

}  // namespace bop::protocol
