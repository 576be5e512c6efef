// Splitting messages into datagrams and putting them back together; layout in UdpFragments.hpp.
#include "transport/UdpFragments.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace bop::protocol {

namespace {

constexpr std::uint8_t kMagic0 = 'B';
constexpr std::uint8_t kMagic1 = 'F';
// Finished sequences remembered per stream. Fragments of a message finished longer ago than
// this arrive after ~256 newer messages (seconds at frame rate), which UDP reordering does not do.
constexpr std::size_t kFinishedHistory = 256;

void putU16(std::uint8_t* p, std::uint16_t v) {
    p[0] = static_cast<std::uint8_t>(v);
    p[1] = static_cast<std::uint8_t>(v >> 8);
}

void putU32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint16_t getU16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}

std::uint32_t getU32(const std::uint8_t* p) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(p[i]) << (8 * i);
    return v;
}

// max(1, ceil(total / stride)) in 64 bits: total and stride come from the wire.
std::uint64_t countFor(std::uint64_t total, std::uint64_t stride) {
    return total == 0 ? 1 : (total + stride - 1) / stride;
}

}  // namespace

std::uint32_t fragmentCount(std::size_t totalBytes, std::size_t payloadBytes) {
    if (payloadBytes < 1 || payloadBytes > kMaxFragmentPayloadBytes)
        throw Error("UDP fragments", "payload of " + std::to_string(payloadBytes) +
                                         " bytes per datagram: expected 1 to " +
                                         std::to_string(kMaxFragmentPayloadBytes));
    if (totalBytes > std::numeric_limits<std::uint32_t>::max())
        throw Error("UDP fragments",
                    "message of " + std::to_string(totalBytes) + " bytes: the datagram header holds at most 2^32 - 1");
    return static_cast<std::uint32_t>(countFor(totalBytes, payloadBytes));
}

void writeFragment(std::vector<std::uint8_t>& out, std::uint8_t stream, std::uint32_t sequence,
                   std::span<const std::uint8_t> message, std::size_t payloadBytes, std::uint32_t index) {
    const std::uint32_t count = fragmentCount(message.size(), payloadBytes);
    if (index >= count)
        throw Error("UDP fragments",
                    "fragment " + std::to_string(index) + " of a message of " + std::to_string(count) + " fragments");
    const std::size_t begin = std::size_t{index} * payloadBytes;
    const std::size_t length = std::min(payloadBytes, message.size() - begin);
    out.resize(kFragmentHeaderBytes + length);
    std::uint8_t* p = out.data();
    p[0] = kMagic0;
    p[1] = kMagic1;
    p[2] = kFragmentVersion;
    p[3] = stream;
    putU32(p + 4, sequence);
    putU32(p + 8, index);
    putU32(p + 12, count);
    putU32(p + 16, static_cast<std::uint32_t>(message.size()));
    putU16(p + 20, static_cast<std::uint16_t>(payloadBytes));
    if (length > 0) std::copy_n(message.data() + begin, length, p + kFragmentHeaderBytes);
}

std::vector<std::vector<std::uint8_t>> splitMessage(std::uint8_t stream, std::uint32_t sequence,
                                                    std::span<const std::uint8_t> message, std::size_t payloadBytes) {
    const std::uint32_t count = fragmentCount(message.size(), payloadBytes);
    std::vector<std::vector<std::uint8_t>> out(count);
    for (std::uint32_t i = 0; i < count; ++i) writeFragment(out[i], stream, sequence, message, payloadBytes, i);
    return out;
}

std::optional<FragmentHeader> readFragmentHeader(std::span<const std::uint8_t> datagram) {
    if (datagram.size() < kFragmentHeaderBytes) return std::nullopt;
    const std::uint8_t* p = datagram.data();
    if (p[0] != kMagic0 || p[1] != kMagic1 || p[2] != kFragmentVersion) return std::nullopt;
    FragmentHeader h;
    h.stream = p[3];
    h.sequence = getU32(p + 4);
    h.index = getU32(p + 8);
    h.count = getU32(p + 12);
    h.totalBytes = getU32(p + 16);
    h.stride = getU16(p + 20);
    if (h.stride == 0 || h.count != countFor(h.totalBytes, h.stride) || h.index >= h.count) return std::nullopt;
    const std::uint64_t begin = std::uint64_t{h.index} * h.stride;  // < totalBytes unless empty
    const std::uint64_t expected = std::min<std::uint64_t>(h.stride, h.totalBytes - begin);
    if (datagram.size() - kFragmentHeaderBytes != expected) return std::nullopt;
    return h;
}

bool sequenceNewer(std::uint32_t a, std::uint32_t b) {
    return static_cast<std::int32_t>(a - b) > 0;  // modular conversion, defined since C++20
}

Reassembler::Reassembler(ReassemblyLimits limits) : limits_(limits) {
    if (limits_.maxPartialMessages == 0 || limits_.maxMessageBytes == 0 ||
        limits_.maxMessageBytes > limits_.maxTotalBytes)
        throw Error("UDP reassembly limits", "expected at least one partial message and 0 < maxMessageBytes (" +
                                                 std::to_string(limits_.maxMessageBytes) + ") <= maxTotalBytes (" +
                                                 std::to_string(limits_.maxTotalBytes) + ")");
}

std::optional<Message> Reassembler::accept(std::span<const std::uint8_t> datagram) {
    ++calls_;
    const std::optional<FragmentHeader> h = readFragmentHeader(datagram);
    if (!h) {
        ++stats_.malformed;
        return std::nullopt;
    }
    const auto payload = datagram.subspan(kFragmentHeaderBytes);
    for (Partial& p : partials_) {
        if (p.header.stream != h->stream || p.header.sequence != h->sequence) continue;
        if (p.header.count != h->count || p.header.totalBytes != h->totalBytes || p.header.stride != h->stride) {
            ++stats_.malformed;
            return std::nullopt;
        }
        return addFragment(p, *h, payload);
    }
    if (h->totalBytes > limits_.maxMessageBytes) {
        ++stats_.oversized;
        return std::nullopt;
    }
    StreamState& s = streams_[h->stream];
    for (const auto& [sequence, outcome] : s.finished) {
        if (sequence != h->sequence) continue;
        ++(outcome == Outcome::Delivered ? stats_.duplicates : stats_.late);
        return std::nullopt;
    }
    if (s.lastDelivered && !sequenceNewer(h->sequence, *s.lastDelivered)) {
        if (h->sequence == *s.lastDelivered) {  // only when the history ring has moved past it
            ++stats_.duplicates;
        } else {
            ++stats_.stale;
            remember(h->stream, h->sequence, Outcome::Stale);
        }
        return std::nullopt;
    }
    if (h->count == 1) return deliver(h->stream, h->sequence, {payload.begin(), payload.end()});

    // A new partial message: make room by giving up the least recently touched ones. The new
    // message fits once all are gone, since maxMessageBytes <= maxTotalBytes.
    while (!partials_.empty() &&
           (partials_.size() >= limits_.maxPartialMessages || bufferedBytes_ + h->totalBytes > limits_.maxTotalBytes)) {
        const auto lru = std::min_element(partials_.begin(), partials_.end(), [](const Partial& a, const Partial& b) {
            return a.lastTouched < b.lastTouched;
        });
        drop(static_cast<std::size_t>(lru - partials_.begin()));
    }
    Partial& p = partials_.emplace_back();
    p.header = *h;
    p.bytes.resize(h->totalBytes);  // zero-filled; bounded by maxMessageBytes
    p.received.assign(h->count, false);
    p.missing = h->count;
    bufferedBytes_ += h->totalBytes;
    return addFragment(p, *h, payload);
}

std::optional<Message> Reassembler::addFragment(Partial& p, const FragmentHeader& h,
                                                std::span<const std::uint8_t> payload) {
    p.lastTouched = calls_;
    if (p.received[h.index]) {
        ++stats_.duplicates;
        return std::nullopt;
    }
    p.received[h.index] = true;
    std::copy(payload.begin(), payload.end(), p.bytes.begin() + std::size_t{h.index} * h.stride);
    if (--p.missing > 0) return std::nullopt;
    std::vector<std::uint8_t> bytes = std::move(p.bytes);
    bufferedBytes_ -= h.totalBytes;
    partials_.erase(partials_.begin() + (&p - partials_.data()));
    return deliver(h.stream, h.sequence, std::move(bytes));
}

std::optional<Message> Reassembler::deliver(std::uint8_t stream, std::uint32_t sequence,
                                            std::vector<std::uint8_t> bytes) {
    streams_[stream].lastDelivered = sequence;
    remember(stream, sequence, Outcome::Delivered);
    ++stats_.delivered;
    // Newest wins: partial messages of this stream not newer than this one can only turn stale.
    for (std::size_t i = partials_.size(); i-- > 0;) {
        const FragmentHeader& ph = partials_[i].header;
        if (ph.stream == stream && !sequenceNewer(ph.sequence, sequence)) drop(i);
    }
    return Message{stream, sequence, std::move(bytes)};
}

void Reassembler::drop(std::size_t partialIndex) {
    const FragmentHeader& ph = partials_[partialIndex].header;
    ++stats_.lost;
    remember(ph.stream, ph.sequence, Outcome::Lost);
    bufferedBytes_ -= ph.totalBytes;
    partials_.erase(partials_.begin() + static_cast<std::ptrdiff_t>(partialIndex));
}

void Reassembler::remember(std::uint8_t stream, std::uint32_t sequence, Outcome outcome) {
    StreamState& s = streams_[stream];
    if (s.finished.size() < kFinishedHistory) {
        s.finished.emplace_back(sequence, outcome);
    } else {
        s.finished[s.finishedNext] = {sequence, outcome};
        s.finishedNext = (s.finishedNext + 1) % kFinishedHistory;
    }
}

}  // namespace bop::protocol
