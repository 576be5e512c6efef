// UdpSender and UdpReceiver: fragmenting, pacing, reading with a deadline.
#include "transport/UdpStream.hpp"

#include <algorithm>
#include <thread>
#include <utility>

namespace bop::protocol {

UdpSender::UdpSender(UdpSocket socket, Endpoint destination, UdpSenderOptions options)
    : socket_(std::move(socket)), destination_(std::move(destination)), options_(options) {
    (void)fragmentCount(0, options_.payloadBytes);  // throws when the payload size is unusable
}

std::uint32_t UdpSender::send(std::uint8_t stream, std::span<const std::uint8_t> message) {
    const std::uint32_t sequence = nextSequence_[stream];
    send(stream, sequence, message);
    return sequence;
}

void UdpSender::send(std::uint8_t stream, std::uint32_t sequence, std::span<const std::uint8_t> message) {
    const std::uint32_t count = fragmentCount(message.size(), options_.payloadBytes);
    nextSequence_[stream] = sequence + 1;  // unsigned: wraps at 2^32
    ++stats_.messages;
    for (std::uint32_t i = 0; i < count; ++i) {
        if (options_.burstDatagrams > 0 && i > 0 && i % options_.burstDatagrams == 0)
            std::this_thread::sleep_for(options_.burstPause);
        writeFragment(datagram_, stream, sequence, message, options_.payloadBytes, i);
        if (socket_.sendTo(destination_, datagram_))
            ++stats_.datagrams;
        else
            ++stats_.datagramsDropped;
    }
}

UdpReceiver::UdpReceiver(UdpSocket socket, ReassemblyLimits limits)
    : socket_(std::move(socket)), reassembler_(limits) {}

bool UdpReceiver::take(Datagram d, std::vector<Message>& newest) {
    ++datagrams_;
    std::optional<Message> m = reassembler_.accept(d.bytes);
    if (!m) return false;
    // The reassembler delivers each stream in increasing sequence order, so a later message
    // of a stream replaces the one held for it.
    const auto same =
        std::find_if(newest.begin(), newest.end(), [&](const Message& n) { return n.stream == m->stream; });
    if (same == newest.end()) {
        newest.push_back(std::move(*m));
    } else {
        *same = std::move(*m);
        ++superseded_;
    }
    return true;
}

std::vector<Message> UdpReceiver::receive(int timeoutMs) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(std::max(timeoutMs, 0));
    std::vector<Message> newest;
    bool complete = false;
    for (std::size_t read = 1;; ++read) {
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
        std::optional<Datagram> d = socket_.receive(static_cast<int>(left.count()));
        if (!d) break;  // nothing more came in time
        complete = take(std::move(*d), newest);
        // Past the deadline, what is queued is still read, but no more than kMaxDrainDatagrams
        // while datagrams keep coming without completing a message.
        if (complete || (read >= kMaxDrainDatagrams && Clock::now() >= deadline)) break;
    }
    for (std::size_t i = 0; complete && i < kMaxDrainDatagrams; ++i) {
        std::optional<Datagram> d = socket_.receive(0);
        if (!d) break;
        take(std::move(*d), newest);
    }
    std::sort(newest.begin(), newest.end(), [](const Message& a, const Message& b) { return a.stream < b.stream; });
    return newest;
}

}  // namespace bop::protocol
