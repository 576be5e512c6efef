#pragma once
// A served session recorded as MCAP (docs/protocol.md "Recording"): the scene, every command
// with the reply that says the step at which it was applied, every probe with the step at
// which it was applied (a Feedback message: probe sequence and step), and every state-frame
// chunk sent, each on its own channel with the binary FlatBuffers schema embedded, so MCAP
// tools can open it; beside them, for every whole frame, the channels Foxglove shows in its 3D and
// Plot panels (FoxgloveChannels.hpp). Chunked, indexed and zstd-compressed (McapWriter.hpp).
// Timestamps are wall-clock nanoseconds since the Unix epoch, taken when a call hands its
// message over.
// The calls only queue copies of their messages: a thread of the recorder's own turns frames into
// Foxglove messages, compresses and writes, so that the front's threads never wait on the disk or
// on zstd. Should it fall kMaxQueuedBytes behind, the recording ends (the next call throws, the
// file stays PATH.partial with what was written), never the run. A failed write shows the same
// way: the next call, or close(), throws bop::Error naming the file.
// The front's threads call a recorder one at a time (under its recordMutex).
#include "codec/Codec.hpp"
#include "recording/FoxgloveChannels.hpp"
#include "recording/McapWriter.hpp"
#include "recording/SessionTopics.hpp"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace bop::protocol {

class SessionRecorder {
public:
    // bop::Error naming the file if it cannot be created. `meta` goes into the scene channel's
    // metadata (scene file, ranks, server options).
    SessionRecorder(const std::string& path, const SceneInfo& scene, const std::map<std::string, std::string>& meta);
    ~SessionRecorder();  // without close(): writes what is queued and leaves PATH.partial unfinished
    SessionRecorder(const SessionRecorder&) = delete;
    SessionRecorder& operator=(const SessionRecorder&) = delete;
    void command(const Buffer& command, const Buffer& reply);
    void probe(const Buffer& probe, const Buffer& applied);  // applied: Feedback with the probe's seq and step
    void frameChunk(const Buffer& chunk);
    void close();  // writes what is queued and finishes the file; throws what the writing thread met
    const std::string& path() const { return writer_.path(); }

    static constexpr std::size_t kMaxQueuedBytes = std::size_t(256) << 20;

private:
    struct Item {
        std::uint16_t channel = 0;  // 0: a frame chunk (also turned into Foxglove messages)
        std::uint64_t timeNs = 0;
        Buffer bytes;
    };
    void push(std::uint16_t channel, const Buffer& b, std::uint64_t timeNs);  // caller holds m_
    void run();                                                               // the writing thread
    void stopThread();

    recording::McapWriter writer_;
    std::uint16_t scene_ = 0, command_ = 0, reply_ = 0, probe_ = 0, applied_ = 0, frame_ = 0;
    std::map<std::uint16_t, std::uint32_t> sequence_;
    FoxgloveChannels foxglove_;

    std::mutex m_;
    std::condition_variable wake_;
    std::deque<Item> queue_;       // guarded by m_
    std::size_t queuedBytes_ = 0;  // guarded by m_
    bool stopping_ = false;        // guarded by m_
    std::exception_ptr error_;     // guarded by m_: what the writing thread met
    std::thread thread_;
};

}  // namespace bop::protocol
