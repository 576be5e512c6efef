#include "recording/SessionReader.hpp"

#include "bop/common/Error.hpp"
#include "recording/McapReader.hpp"
#include "recording/SessionTopics.hpp"

#include <deque>

namespace bop::protocol {
namespace {

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

template <class T>
T need(const Decoded<T>& d, const std::string& path, std::size_t index, const char* what) {
    if (!d) throw Error(path, std::string("message ") + std::to_string(index) + " (" + what + "): " + d.message);
    return d.value;
}

}  // namespace

RecordedSession readSession(const std::string& path) {
    const bool partial = endsWith(path, ".partial");
    const recording::McapFile f =
        recording::readMcap(path, partial ? recording::McapReadMode::Tolerant : recording::McapReadMode::Strict);
    std::map<std::uint16_t, std::string> topic;
    RecordedSession s;
    bool scene = false;
    for (const auto& c : f.channels) {
        topic[c.id] = c.topic;
        if (c.topic == kTopicScene) s.meta = c.metadata;
    }
    std::deque<Command> commands;  // waiting for their replies
    std::deque<Probe> probes;      // waiting for their steps
    for (std::size_t k = 0; k < f.messages.size(); ++k) {
        const auto& m = f.messages[k];
        const std::string& t = topic[m.channelId];
        const std::uint8_t* d = m.data.data();
        const std::size_t n = m.data.size();
        if (t == kTopicScene) {
            s.scene = need(decodeSceneInfo(d, n), path, k, "scene");
            scene = true;
        } else if (t == kTopicCommand) {
            commands.push_back(need(decodeCommand(d, n), path, k, "command"));
        } else if (t == kTopicReply) {
            const CommandReply r = need(decodeCommandReply(d, n), path, k, "reply");
            if (commands.empty() || commands.front().requestId != r.requestId)
                throw Error(path, "message " + std::to_string(k) + ": a reply without its command");
            s.commands.push_back({commands.front(), r});
            commands.pop_front();
        } else if (t == kTopicProbe) {
            probes.push_back(need(decodeProbe(d, n), path, k, "probe"));
        } else if (t == kTopicProbeApplied) {
            const Feedback a = need(decodeFeedback(d, n), path, k, "probe step");
            if (probes.empty() || probes.front().seq != a.probeSeq)
                throw Error(path, "message " + std::to_string(k) + ": a probe step without its probe");
            s.probes.push_back({probes.front(), a.step});
            probes.pop_front();
        } else if (t == kTopicFrame) {
            FrameLimits limits;
            limits.maxChunkBytes = kAbsoluteMaxBytes;
            s.chunks.push_back({m.logTimeNs, m.data, need(decodeStateFrame(d, n, limits), path, k, "frame")});
        }
    }
    if (!scene) throw Error(path, "no scene message: not a BoP session recording");
    return s;
}

}  // namespace bop::protocol
