#pragma once
// The front's state (ServerFront.hpp) in three parts, each guarding its own:
//  - the sessions (`m`): the control thread's clients, refusals, answers and counts
//    (ServerFront.cpp, FrontSessions.cpp, FrontMap.cpp);
//  - the inbound slots (`inbound.m`): commands and the newest probe in, replies and feedback out,
//    the inputs to record; the step loop's side of them is FrontLoopSide.cpp;
//  - the frame slot and the publisher (`frames.m`): the frame offered, the spare one, the
//    publisher's counts (FrontPublisher.cpp).
// The step loop locks only the slots, so it never waits on the sessions; the control thread
// takes the inbound slots' lock inside the sessions' (never the other way round).
#include "codec/BufferPool.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "recording/SessionRecorder.hpp"
#include "security/ZapHandler.hpp"
#include "server/FrontUdp.hpp"
#include "server/ServerFront.hpp"

#include <zmq.hpp>

#include <condition_variable>
#include <functional>
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
inline constexpr std::size_t kMaxSessions = 4096;           // beyond: a Hello is refused ("server full")
inline constexpr int kRefusalsPerSecond = 4;                // Refusal messages to one session a second
inline constexpr int kAnonymousRefusalsPerSecond = 16;      // to identities without a session, all together

inline std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// At most `perSecond` events in any one second (a fixed window restarted by the first event after it).
struct Budget {
    Clock::time_point second{};
    int used = 0;
    bool take(Clock::time_point now, int perSecond) {
        if (now - second > std::chrono::seconds(1)) second = now, used = 0;
        return ++used <= perSecond;
    }
};

// The step loop's waits for a slot's lock (FrontStats::loopWait*), kept under that lock.
struct LoopWaits {
    std::uint64_t count = 0;
    double longestMs = 0, totalMs = 0;
};

struct InboundSlots {
    mutable std::mutex m;  // guards the fields below
    std::vector<PendingCommand> commands;
    std::optional<Probe> probe;
    std::optional<Feedback> feedback;
    std::vector<std::pair<std::string, Buffer>> replies;
    std::vector<std::pair<Buffer, Buffer>> toRecord;       // (command, reply) or (probe, applied)
    std::shared_ptr<const std::vector<MapEdit>> mapEdits;  // the map's edits so far (FrontMap.cpp); null: none
    LoopWaits waits;
};

struct FrameSlot {
    mutable std::mutex m;             // guards the fields below
    std::condition_variable offered;  // wakes the publisher
    bool stop = false;                // the publisher ends once the slot is empty
    std::optional<StateFrame> frame;  // offered, not yet taken by the publisher
    std::optional<std::vector<Buffer>> encoded;
    StateFrame spare;  // the last frame published, its memory for the next gather
    std::uint64_t sent = 0, dropped = 0, bytes = 0;
    std::string publishError;
    LoopWaits waits;
};

struct Client {
    bool mayCommand = true;
    float wantedHz = 0;
    std::string udpAddress;  // where its frame datagrams go (empty: none)
    std::uint16_t udpPort = 0;
    int udpTier = 0;
    Clock::time_point lastHeard{};  // any message: a session silent for the timeout is forgotten
    Clock::time_point lastProbe{};
    Budget mapPieces;           // the gradient-map download's budget (FrontMap.cpp)
    Budget refusals;            // Refusal messages sent to it
    std::uint64_t refused = 0;  // its messages refused so far
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
    int wakeFd = -1;        // eventfd: the step loop's offers wake the control thread at once (feedback latency)
    // Chunk buffers ZeroMQ has sent, for the next frames; held weakly by messages in flight.
    std::shared_ptr<BufferPool> chunkPool = std::make_shared<BufferPool>(front::kKeptChunkBuffers);

    front::InboundSlots inbound;  // between the step loop and the control thread, under its own lock
    front::FrameSlot frames;      // between the step loop and the publisher, under its own lock

    // The sessions' lock: guards what follows but the atomics, frameNumber (the publisher's own),
    // nextTick (the step loop's own) and the recorder (which recordMutex guards as well).
    mutable std::mutex m;
    std::condition_variable helloSeen;
    std::unique_ptr<SessionRecorder> recorder;  // guarded by recordMutex once the threads run
    std::atomic<bool> recording{false};         // recorder is set (read by the step loop without a lock)
    std::unique_ptr<ZapHandler> zap;            // the control thread's, once it runs
    std::unique_ptr<FrontUdp> udp;              // used by the threads only (FrontUdp.hpp says how)
    std::map<std::string, front::Client> clients;
    FrontStats stats;
    std::atomic<float> rateHz{60};
    std::atomic<bool> haptic{false};
    std::atomic<std::uint64_t> particleCount{0};
    std::uint64_t frameNumber = 0;  // frames published (tier of the next one); the publisher's
    std::mutex recordMutex;         // the recorder is written by both threads
    Clock::time_point nextTick{};   // step loop's publish clock

    int bind(zmq::socket_t& s, int port);
    void configure(zmq::socket_t& s);
    void sendTo(const std::string& id, const Buffer& b);
    SceneInfo sceneNow();
    // ---- inbound messages and sessions (FrontSessions.cpp), all with m held; they put commands
    // and probes into the inbound slots, taking inbound.m inside m ----
    // One inbound message from peer `id`; its answers go to `outbox`. `peerAddress` gives the
    // peer's IP address (asked only for a Hello naming a UDP frame port). Never throws: trouble
    // handling it is counted as an internal error.
    void handle(const std::string& id, const std::uint8_t* data, std::size_t size,
                const std::function<std::string()>& peerAddress);
    void dispatch(const std::string& id, const std::uint8_t* data, std::size_t size,
                  const std::function<std::string()>& peerAddress);
    void hello(const std::string& id, const Decoded<Hello>& h, const std::function<std::string()>& peerAddress);
    void command(const std::string& id, const Decoded<Command>& c);
    // Refusals: counted by their error (None: refused by policy, counted in neither malformed nor
    // outOfRange) and answered, a command by its reply, anything else by a Refusal within the
    // peer's budget.
    void count(DecodeError error);
    void refuse(const std::string& id, const Command& c, ReplyStatus status, DecodeError error, const std::string& why);
    void refuse(const std::string& id, MessageKind kind, std::uint64_t seq, DecodeError error, const std::string& why);
    void expire(Clock::time_point now);                  // forgets the sessions silent for opt.sessionTimeout
    void updateRate();                                   // the largest rate a session wants, within the bounds
    void internalError(const std::string& what);         // counted, said on stderr sparingly; m held
    std::vector<std::pair<std::string, Buffer>> outbox;  // answers of handle(), sent by the loop
    front::Budget anonymousRefusals;
    Clock::time_point nextExpiry{};
    Buffer mapPiece(const MapRequest& r, front::Client& c);  // FrontMap.cpp
    Buffer mapEdits(const MapEditsRequest& r, front::Client& c);
    int mapPiecesThisPass = 0;  // at most kMapPiecesPerPass per pass of the loop
    // ---- the publisher (FrontPublisher.cpp) ----
    void publish(StateFrame f);
    void send(std::vector<Buffer> chunks);
    // Runs a recorder call; a failure (disk full, ...) ends the recording, never the server.
    template <class F>
    void record(F f) {
        std::lock_guard recording(recordMutex);
        recordLocked(f);
    }
    void recordInputLocked(
        const std::pair<Buffer, Buffer>& input);  // (command, reply) or (probe, applied); recordMutex held
    template <class F>
    void recordLocked(F f) {  // recordMutex held
        if (!recorder) return;
        try {
            f();
        } catch (const std::exception& e) {
            std::lock_guard lock(m);
            stats.recordError = e.what();
            recorder.reset();
            recording = false;
        }
    }
    void loop();
    void pass(std::vector<zmq::pollitem_t>& items);  // one pass of loop(): in, then out
    void publisherLoop();
    void wake();  // from the step loop, after an offer to the control thread
};

}  // namespace bop::protocol
