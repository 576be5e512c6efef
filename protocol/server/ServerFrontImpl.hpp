#pragma once
// The front's state (ServerFront.hpp), shared by its thread's side (ServerFront.cpp: sockets,
// handshakes, publishing) and the step loop's side (ServerFrontSlots.cpp: the slots).
#include "server/ServerFront.hpp"

#include "codec/BufferPool.hpp"
#include "codec/Codec.hpp"
#include "server/FrontUdp.hpp"
#include "server/SessionRecorder.hpp"
#include "server/ZapHandler.hpp"

#include <zmq.hpp>

#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>

namespace bop::protocol {
namespace front {

using Clock = std::chrono::steady_clock;
inline constexpr std::size_t kMaxInboundBytes = 64 * 1024;  // ZeroMQ drops larger messages and their peer
inline constexpr std::size_t kMaxQueuedCommands = 1024;     // beyond: refused as the step loop is behind
inline constexpr int kPubHighWaterMark = 64;                // messages queued per subscriber before PUB drops
inline constexpr std::size_t kKeptChunkBuffers = 16;        // frame chunk buffers kept for reuse (BufferPool)

inline std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

struct Client {
    bool mayCommand = true;
    float wantedHz = 0;
    Clock::time_point lastProbe{};
    Clock::time_point mapSecond{};  // the gradient-map download's budget: pieces in this second
    int mapPieces = 0;
};

}  // namespace front

struct ServerFront::Impl {
    using Clock = front::Clock;
    FrontOptions opt;
    SceneInfo scene;
    zmq::context_t ctx{1};
    zmq::socket_t router{ctx, zmq::socket_type::router}, pub{ctx, zmq::socket_type::pub};
    int controlPort = 0, framePort = 0;
    std::string controlEndpoint;
    std::atomic<bool> stop{false};
    std::thread thread;     // control: handshakes, commands, probes in, feedback out
    std::thread publisher;  // frames out: encoding a large frame never holds back a feedback
    int wakeFd = -1;  // eventfd: the step loop's offers wake the control thread at once (feedback latency)
    // Chunk buffers ZeroMQ has sent, for the next frames; held weakly by messages in flight.
    std::shared_ptr<BufferPool> chunkPool = std::make_shared<BufferPool>(front::kKeptChunkBuffers);

    mutable std::mutex m;  // guards everything below
    std::condition_variable helloSeen;
    std::condition_variable frameOffered;  // wakes the publisher
    std::vector<PendingCommand> commands;
    std::optional<Probe> probe;
    std::optional<StateFrame> frame;
    StateFrame spareFrame;  // the last frame published, its memory for the next gather
    std::optional<std::vector<Buffer>> encodedFrame;
    std::optional<Feedback> feedback;
    std::vector<std::pair<std::string, Buffer>> replies;
    std::vector<std::pair<Buffer, Buffer>> toRecord;  // (command, reply) or (probe, applied)
    std::unique_ptr<SessionRecorder> recorder;        // guarded by recordMutex once the threads run
    std::unique_ptr<ZapHandler> zap;                  // the control thread's, once it runs
    std::unique_ptr<FrontUdp> udp;                    // used by the threads only (FrontUdp.hpp says how)
    std::map<std::string, front::Client> clients;
    FrontStats stats;
    std::atomic<float> rateHz{60};
    std::atomic<bool> haptic{false};
    std::uint64_t particleCount = 0;
    std::uint64_t frameNumber = 0;   // frames published (tier of the next one); the publisher's
    std::mutex recordMutex;          // the recorder is written by both threads
    Clock::time_point nextTick{};    // step loop's publish clock

    int bind(zmq::socket_t& s, int port);
    void configure(zmq::socket_t& s);
    void sendTo(const std::string& id, const Buffer& b);
    SceneInfo sceneNow();
    void refuse(const std::string& id, const Command& c, ReplyStatus status, const std::string& why);
    // One inbound message from peer `id` (m held).
    void handle(const std::string& id, zmq::message_t& msg);
    Buffer mapPiece(const MapRequest& r, front::Client& c);  // FrontMap.cpp
    int mapPiecesThisPass = 0;             // at most kMapPiecesPerPass per pass of the loop
    void publish(StateFrame f);
    void send(std::vector<Buffer> chunks);
    // Runs a recorder call; a failure (disk full, ...) ends the recording, never the server.
    template <class F> void record(F f) {
        std::lock_guard recording(recordMutex);
        recordLocked(f);
    }
    template <class F> void recordLocked(F f) {  // recordMutex held
        if (!recorder) return;
        try {
            f();
        } catch (const std::exception& e) {
            std::lock_guard lock(m);
            stats.recordError = e.what();
            recorder.reset();
        }
    }
    void loop();
    void publisherLoop();
    void wake();  // from the step loop, after an offer to the control thread
};

}  // namespace bop::protocol
