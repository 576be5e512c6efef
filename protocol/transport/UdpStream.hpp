#pragma once
// Datagram mode end to end: UdpSender splits each message into fragments (UdpFragments.hpp) and
// sends them to one peer; UdpReceiver reads its socket for a bounded time and hands out the
// newest complete message of each stream. Neither retransmits: a lost fragment loses its
// message, and the next one (the next frame) replaces it.
#include "transport/UdpFragments.hpp"
#include "transport/UdpSocket.hpp"

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace bop::protocol {

// Stream id of state frames in the datagram header (the server's frames to UDP clients).
inline constexpr std::uint8_t kUdpFrameStream = 1;

struct UdpSenderOptions {
    std::size_t payloadBytes = kDefaultFragmentPayloadBytes;  // per datagram, header excluded
    // Pacing: after every burstDatagrams datagrams (0: never) sleep burstPause. A 3 MB frame sent
    // back to back can overrun the receiver's socket buffer or a switch queue; a short pause
    // every few hundred datagrams lets them drain at a small cost in latency.
    std::size_t burstDatagrams = 0;
    std::chrono::microseconds burstPause{0};
};

struct UdpSenderStats {
    std::uint64_t messages = 0;          // send() calls
    std::uint64_t datagrams = 0;         // datagrams handed to the kernel
    std::uint64_t datagramsDropped = 0;  // refused by the kernel (UdpSocket::sendTo false)
};

class UdpSender {
public:
    // Throws bop::Error when options.payloadBytes is outside [1, kMaxFragmentPayloadBytes].
    UdpSender(UdpSocket socket, Endpoint destination, UdpSenderOptions options = {});

    // Sends message as the next sequence of stream (sequences count from 0 per stream and
    // wrap at 2^32); returns the sequence used. Throws as UdpSocket::sendTo and fragmentCount.
    std::uint32_t send(std::uint8_t stream, std::span<const std::uint8_t> message);
    // Sends with an explicit sequence; the stream's next sequence becomes sequence + 1.
    void send(std::uint8_t stream, std::uint32_t sequence, std::span<const std::uint8_t> message);

    const UdpSenderStats& stats() const { return stats_; }
    UdpSocket& socket() { return socket_; }
    const Endpoint& destination() const { return destination_; }

private:
    UdpSocket socket_;
    Endpoint destination_;
    UdpSenderOptions options_;
    UdpSenderStats stats_;
    std::array<std::uint32_t, 256> nextSequence_{};  // by stream id
    std::vector<std::uint8_t> datagram_;             // reused for every fragment
};

class UdpReceiver {
public:
    // Datagrams read past the deadline, or after a message completed, are at most about this
    // many, so that a sender faster than the reader cannot keep receive() from returning.
    static constexpr std::size_t kMaxDrainDatagrams = 8192;

    explicit UdpReceiver(UdpSocket socket, ReassemblyLimits limits = {});

    // Reads datagrams until a message completes or timeoutMs milliseconds have passed (0: only
    // what is queued now), then also reads what is already queued. Returns the newest complete
    // message of each stream, by stream id (empty on timeout); older ones completed in the same
    // call are superseded.
    std::vector<Message> receive(int timeoutMs);

    const ReassemblyStats& stats() const { return reassembler_.stats(); }
    std::uint64_t superseded() const { return superseded_; }  // delivered, then replaced
    std::uint64_t datagrams() const { return datagrams_; }    // read from the socket
    std::size_t partialMessages() const { return reassembler_.partialMessages(); }
    UdpSocket& socket() { return socket_; }

private:
    bool take(Datagram d, std::vector<Message>& newest);  // true when a message completed

    UdpSocket socket_;
    Reassembler reassembler_;
    std::uint64_t superseded_ = 0;
    std::uint64_t datagrams_ = 0;
};

}  // namespace bop::protocol
