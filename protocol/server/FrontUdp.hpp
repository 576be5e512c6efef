#pragma once
// The front's datagram side (the paper's UDP mode, docs/protocol.md): probes arrive as single
// datagrams on port P+2 and get their feedback back as datagrams; clients that named a UDP
// frame port in their Hello get every 2^m-th frame (m from their wanted rate) as one
// fragmented message (transport/UdpStream.hpp). The front's control thread calls everything but
// frame(), which its publisher calls; frame clients are guarded, each has its own socket.
#include "codec/Codec.hpp"
#include "transport/UdpStream.hpp"

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

namespace bop::protocol {

class FrontUdp {
public:
    using Clock = std::chrono::steady_clock;
    static constexpr std::uint8_t kFrameStream = kUdpFrameStream;

    FrontUdp(const std::string& bindAddress, int port);  // port 0: ephemeral
    int port() const { return socket_.boundPort(); }
    int fd() const { return socket_.fd(); }  // readable when probes are queued

    struct Inbound {
        std::optional<Probe> newest;  // the newest valid probe that came
        std::uint64_t probes = 0, malformed = 0, oversized = 0;
        std::uint64_t outOfRange = 0;    // probes refused for a value (decoder or the scene's ranges)
        std::uint64_t refusalsSent = 0;  // Refusal datagrams sent back
    };
    // What is queued now, without waiting; probes are checked against the scene's ranges
    // (InboundRanges.hpp) and a refused one that could be read is answered with a Refusal
    // datagram no larger than it, at most one a second to an address (garbage is only counted:
    // a datagram's sender may be forged).
    Inbound poll(Clock::time_point now, const SceneInfo& scene);
    void feedback(const Buffer& b, Clock::time_point now);  // to probe senders of the last second
    bool anyProbing(Clock::time_point now) const;

    // A client (by identity) that wants frames at `address:port`, every 2^tier-th frame (port 0:
    // no more frames). False when kMaxFrameClients other clients already get them.
    static constexpr std::size_t kMaxFrameClients = 64;
    bool setFrameClient(const std::string& id, const std::string& address, std::uint16_t port, int tier);
    void setFrameTier(const std::string& id, int tier);  // the same client, another rate
    // The whole frame (one buffer), the frame's number (from 1) decides which clients get it.
    void frame(const Buffer& whole, std::uint64_t frameNumber);
    bool wantsFrame(std::uint64_t frameNumber) const;  // some client gets frame `frameNumber`
    std::uint64_t datagramsDropped() const;

private:
    UdpSocket socket_;
    std::map<std::string, Clock::time_point> probers_;  // "address:port" -> last probe
    struct Refused {
        Clock::time_point lastSent{};
        std::uint64_t count = 0;
    };
    // By IP address (any port): a sender that forges its address gets one Refusal a second per
    // address, and all of them together at most kRefusalsPerSecond; forgotten after a quiet second.
    static constexpr int kRefusalsPerSecond = 16;
    std::map<std::string, Refused> refused_;
    Clock::time_point refusalSecond_{};
    int refusalsThisSecond_ = 0;
    void refuse(const Endpoint& sender, const Probe* p, DecodeError e, const std::string& why, Clock::time_point now,
                Inbound& in, std::size_t datagramBytes);
    std::uint64_t sendFailures_ = 0;  // datagrams that could not be sent (said on stderr, sparingly)
    struct FrameClient {
        std::unique_ptr<UdpSender> sender;
        int tier = 0;
    };
    mutable std::mutex frameMutex_;  // guards frameClients_
    std::map<std::string, FrameClient> frameClients_;
};

}  // namespace bop::protocol
