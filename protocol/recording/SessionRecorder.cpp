#include "recording/SessionRecorder.hpp"

#include "bop/common/Error.hpp"

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
    const std::uint64_t t = wallNs();
    writer_.write(scene_, sequence_[scene_]++, t, t, encodeSceneInfo(scene));
    thread_ = std::thread([this] { run(); });
}

SessionRecorder::~SessionRecorder() {
    stopThread();  // what is queued is written; the writer's destructor leaves PATH.partial
}

void SessionRecorder::push(std::uint16_t channel, const Buffer& b, std::uint64_t timeNs) {
    if (error_) std::rethrow_exception(error_);
    if (queuedBytes_ + b.size() > kMaxQueuedBytes) {
        queue_.clear();  // the disk cannot keep up: end the recording here, the run goes on
        queuedBytes_ = 0;
        error_ = std::make_exception_ptr(Error(writer_.partialPath(), "the recording fell " +
                                                                          std::to_string(kMaxQueuedBytes >> 20) +
                                                                          " MiB behind the session (disk too slow?)"));
        std::rethrow_exception(error_);
    }
    queuedBytes_ += b.size();
    queue_.push_back({channel, timeNs, b});
}

void SessionRecorder::command(const Buffer& command, const Buffer& reply) {
    const std::uint64_t t = wallNs();
    {
        std::lock_guard lock(m_);
        push(command_, command, t);
        push(reply_, reply, t);
    }
    wake_.notify_one();
}

void SessionRecorder::probe(const Buffer& probe, const Buffer& applied) {
    const std::uint64_t t = wallNs();
    {
        std::lock_guard lock(m_);
        push(probe_, probe, t);
        push(applied_, applied, t);
    }
    wake_.notify_one();
}

void SessionRecorder::frameChunk(const Buffer& chunk) {
    const std::uint64_t t = wallNs();
    {
        std::lock_guard lock(m_);
        push(0, chunk, t);
    }
    wake_.notify_one();
}

void SessionRecorder::run() {
    std::unique_lock lock(m_);
    for (;;) {
        wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping, and everything is written
        Item item = std::move(queue_.front());
        queue_.pop_front();
        queuedBytes_ -= item.bytes.size();
        if (error_) continue;  // after a failure nothing more is written
        lock.unlock();
        try {
            const std::uint16_t channel = item.channel == 0 ? frame_ : item.channel;
            writer_.write(channel, sequence_[channel]++, item.timeNs, item.timeNs, item.bytes);
            if (item.channel == 0) foxglove_.frameChunk(item.bytes, item.timeNs);
            lock.lock();
        } catch (...) {
            lock.lock();
            error_ = std::current_exception();
        }
    }
}

void SessionRecorder::stopThread() {
    {
        std::lock_guard lock(m_);
        stopping_ = true;
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
}

void SessionRecorder::close() {
    stopThread();
    if (error_) std::rethrow_exception(error_);
    writer_.close();
}

}  // namespace bop::protocol
