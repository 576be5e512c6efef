#pragma once
// Datagram mode of the protocol: a message (an encoded state frame of several MB, a probe) is
// split into UDP datagrams small enough to pass an Ethernet MTU unfragmented, and put back
// together on the other side. UDP loses, duplicates and reorders datagrams, and anyone can send
// to the port, so the Reassembler checks every datagram, keeps bounded state, and hands out only
// complete messages, newest first ("newest wins": an old frame is worth nothing once a newer one
// has been shown).
//
// Datagram layout (little-endian, 22-byte header, then the payload):
//   offset  size  field
//   0       2     magic "BF"
//   2       1     header version (kFragmentVersion)
//   3       1     stream id (frames, probe, ...: sequences are counted per stream)
//   4       4     message sequence (u32, wraps; compared with serial-number arithmetic)
//   8       4     fragment index (u32, < count)
//   12      4     fragment count (u32: a 32 MB frame at 1200 bytes needs ~28000 fragments)
//   16      4     total message bytes (u32)
//   20      2     stride: payload bytes of every fragment but the last (u16, >= 1)
//   22      ...   payload: bytes [index * stride, index * stride + length) of the message
// count must equal max(1, ceil(total / stride)) and the payload length must be stride for every
// fragment but the last, which carries the remainder; so any truncation of a datagram is seen.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace bop::protocol {

inline constexpr std::uint8_t kFragmentVersion = 1;
inline constexpr std::size_t kFragmentHeaderBytes = 22;
// 1200 payload + 22 header + 8 UDP + 40 IPv6 (or 20 IPv4) headers fits a 1500-byte MTU with room
// for tunnels (VPN, VXLAN), so no IP-level fragmentation happens on the way.
inline constexpr std::size_t kDefaultFragmentPayloadBytes = 1200;
// Largest UDP payload over IPv4 (65507 bytes) less the header.
inline constexpr std::size_t kMaxFragmentPayloadBytes = 65507 - kFragmentHeaderBytes;

struct FragmentHeader {
    std::uint8_t stream = 0;
    std::uint32_t sequence = 0;
    std::uint32_t index = 0;
    std::uint32_t count = 1;
    std::uint32_t totalBytes = 0;
    std::uint16_t stride = 1;
};

// Fragments needed for a message of totalBytes at payloadBytes each (at least 1: an empty
// message is one empty fragment). Throws bop::Error when the message exceeds the u32 size field
// or payloadBytes is outside [1, kMaxFragmentPayloadBytes].
std::uint32_t fragmentCount(std::size_t totalBytes, std::size_t payloadBytes);

// Writes datagram `index` of `message` into `out` (resized; reused by senders so that a 3 MB
// message does not allocate 2600 vectors). Throws as fragmentCount, or if index >= count.
void writeFragment(std::vector<std::uint8_t>& out, std::uint8_t stream, std::uint32_t sequence,
                   std::span<const std::uint8_t> message, std::size_t payloadBytes, std::uint32_t index);

// All datagrams of a message, in index order.
std::vector<std::vector<std::uint8_t>> splitMessage(std::uint8_t stream, std::uint32_t sequence,
                                                    std::span<const std::uint8_t> message,
                                                    std::size_t payloadBytes = kDefaultFragmentPayloadBytes);

// The header of a datagram that is well formed on its own (size, magic, version, index < count,
// count consistent with total and stride, payload length as the header implies), else nullopt.
std::optional<FragmentHeader> readFragmentHeader(std::span<const std::uint8_t> datagram);

// True when sequence a comes after b, modulo 2^32 (RFC 1982): a - b read as int32 is positive.
// Exactly 2^31 apart is neither newer nor older.
bool sequenceNewer(std::uint32_t a, std::uint32_t b);

struct ReassemblyLimits {
    std::size_t maxPartialMessages = 4;       // messages being assembled at once, all streams
    std::size_t maxMessageBytes = 32u << 20;  // one message; larger ones are refused (bytes)
    std::size_t maxTotalBytes = 64u << 20;    // all partial messages together (bytes)
};

// Datagram counters (duplicates, late, malformed, oversized) and message counters (delivered,
// lost, stale). Every message of which one well-formed datagram arrived is counted once as
// delivered, lost or stale, or is still partial: delivered + lost + stale + partial = messages.
struct ReassemblyStats {
    std::uint64_t delivered = 0;   // messages complete and handed out
    std::uint64_t lost = 0;        // partial messages given up: superseded by a newer complete
                                   // message of their stream, or evicted to respect the limits
    std::uint64_t stale = 0;       // messages older than the last delivered of their stream
    std::uint64_t duplicates = 0;  // datagrams already held, or of a message already delivered
    std::uint64_t late = 0;        // datagrams of a message already counted lost or stale
    std::uint64_t malformed = 0;   // datagrams failing readFragmentHeader, or disagreeing with
                                   // earlier fragments of their message on count/total/stride
    std::uint64_t oversized = 0;   // datagrams of a message larger than maxMessageBytes
};

struct Message {
    std::uint8_t stream = 0;
    std::uint32_t sequence = 0;
    std::vector<std::uint8_t> bytes;
};

class Reassembler {
public:
    // Throws bop::Error when a limit is zero or maxMessageBytes > maxTotalBytes.
    explicit Reassembler(ReassemblyLimits limits = {});

    // Takes one datagram (untrusted bytes); returns the message it completes, if any.
    std::optional<Message> accept(std::span<const std::uint8_t> datagram);

    const ReassemblyStats& stats() const { return stats_; }
    std::size_t partialMessages() const { return partials_.size(); }
    std::size_t bufferedBytes() const { return bufferedBytes_; }  // reserved by partials

private:
    enum class Outcome : std::uint8_t { Delivered, Lost, Stale };
    struct Partial {
        FragmentHeader header;            // index unused
        std::vector<std::uint8_t> bytes;  // totalBytes, filled as fragments arrive
        std::vector<bool> received;       // one flag per fragment
        std::uint32_t missing = 0;        // fragments not yet received
        std::uint64_t lastTouched = 0;    // accept() call number, for least-recent eviction
    };
    struct StreamState {
        std::optional<std::uint32_t> lastDelivered;
        // Recently finished sequences, so that late fragments of a message are not counted
        // again: a ring of at most kFinishedHistory entries, next overwritten at finishedNext.
        std::vector<std::pair<std::uint32_t, Outcome>> finished;
        std::size_t finishedNext = 0;
    };

    std::optional<Message> addFragment(Partial& p, const FragmentHeader& h, std::span<const std::uint8_t> payload);
    std::optional<Message> deliver(std::uint8_t stream, std::uint32_t sequence, std::vector<std::uint8_t> bytes);
    void drop(std::size_t partialIndex);  // gives up a partial message: counted lost
    void remember(std::uint8_t stream, std::uint32_t sequence, Outcome outcome);

    ReassemblyLimits limits_;
    ReassemblyStats stats_;
    std::vector<Partial> partials_;         // at most maxPartialMessages: searched linearly
    std::array<StreamState, 256> streams_;  // by stream id
    std::size_t bufferedBytes_ = 0;
    std::uint64_t calls_ = 0;
};

}  // namespace bop::protocol
