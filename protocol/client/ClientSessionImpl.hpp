#pragma once
// ClientSession's state, shared by its control side (ClientSession.cpp: DEALER, handshake,
// commands, probes, feedback) and its frame side (ClientFrames.cpp: SUB, reassembly, the
// receiver thread).
#include "client/ClientSession.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "transport/UdpStream.hpp"

#include <zmq.hpp>

#include <atomic>
#include <mutex>
#include <thread>

namespace bop::protocol {

struct ClientSession::Impl {
    using Clock = std::chrono::steady_clock;

    ClientOptions opt;
    zmq::context_t ctx{1};
    std::optional<zmq::socket_t> dealer, sub;  // made by connect()
    std::string controlEndpoint, frameEndpoint;
    SceneInfo scene;
    int tier = 0;
    std::optional<Feedback> feedback;      // newest not yet polled
    std::optional<MapEdits> mapEdits;      // newest answer not yet taken
    std::optional<Refusal> refusal;        // newest not yet looked at by connect() or sendCommand()
    Buffer hello;                          // this session's Hello, sent again to keep the session
    Clock::time_point lastSent{};          // the last message over the DEALER socket
    std::optional<UdpSocket> probeSocket;  // ClientOptions::probeOverUdp
    Endpoint probeTo;                      // the server's UDP probe port

    // Frame side: used by the caller's thread, or only by the receiver thread while it runs.
    FrameAssembler assembler;
    FrameLimits frameLimits;
    std::optional<UdpReceiver> udpFrames;  // ClientOptions::udpFramePort
    std::thread receiver;
    std::atomic<bool> stopReceiver{false};
    std::atomic<bool> running{false};  // the receiver thread is in its loop

    mutable std::mutex m;  // guards everything below
    ClientStats stats;
    LatestFrame latest;
    std::string receiverError;

    explicit Impl(ClientOptions o) : opt(std::move(o)), assembler(opt.assembler) {}

    // ---- control side (ClientSession.cpp) ----
    void setCommonOptions(zmq::socket_t& s, std::size_t maxMessageBytes);
    void connectSub();
    // Handles one DEALER message: keeps SceneInfo and feedback, puts a reply in *reply (counted
    // as dropped when reply is null). Returns what it decoded; Unknown when refused (counted).
    MessageKind takeControl(const zmq::message_t& msg, CommandReply* reply);
    void countMalformed();
    // Reads DEALER messages, handing each to `take`, until it returns true (then true) or
    // `deadline` passes (then false, having read everything queued).
    template <class Take>
    bool pumpControl(Clock::time_point deadline, Take take);
    // Waits until `s` (or file descriptor `fd`, if not -1) has something to read or `deadline`
    // passes; false at the deadline or when a signal interrupted the wait (callers look at the
    // clock again).
    static bool waitReadable(zmq::socket_t& s, Clock::time_point deadline, int fd = -1);
    void takeUdpFeedback();  // feedback datagrams queued on probeSocket
    void takeRefusal(Refusal r);
    void send(const Buffer& b, const char* what);  // over the DEALER, without waiting; bop::Error when it cannot queue
    void keepAlive();  // Hello again when a third of the server's session timeout went by in silence

    // ---- frame side (ClientFrames.cpp) ----
    // Reads every frame message queued on the SUB socket without waiting; returns the newest
    // whole frame they completed, if any.
    std::optional<StateFrame> drainSub();
    std::optional<StateFrame> drainUdp();     // the same for frames over UDP
    std::optional<StateFrame> drainFrames();  // from whichever of the two carries frames
    int udpFrameFd() { return udpFrames ? udpFrames->socket().fd() : -1; }
    // One frame chunk, from whatever transport carried it (the SUB socket, or a whole frame from
    // the UDP receiver): decoded, counted, fed to the assembler.
    std::optional<StateFrame> takeChunk(const std::uint8_t* data, std::size_t size);
    void receiverLoop() noexcept;
    void joinReceiver();
    void syncAssemblerStats();  // m held
};

// Multi-part messages are not ours: counted as malformed.
template <class Take>
bool ClientSession::Impl::pumpControl(Clock::time_point deadline, Take take) {
    for (;;) {
        zmq::message_t msg;
        while (dealer->recv(msg, zmq::recv_flags::dontwait)) {
            if (!msg.more()) {
                if (take(msg)) return true;
                continue;
            }
            for (zmq::message_t part; msg.more() && dealer->recv(part, zmq::recv_flags::dontwait);)
                msg = std::move(part);
            countMalformed();
        }
        if (Clock::now() >= deadline) return false;
        waitReadable(*dealer, deadline);
    }
}

}  // namespace bop::protocol
