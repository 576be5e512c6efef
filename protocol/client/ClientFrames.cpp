// ClientSession's frame side: the SUB socket, chunk decoding and reassembly, and the receiver
// thread that keeps the newest whole frame for a renderer.
#include "client/ClientSessionImpl.hpp"
#include "codec/Codec.hpp"

#include <algorithm>
#include <stdexcept>

namespace bop::protocol {
namespace {

using Clock = std::chrono::steady_clock;

// How often the receiver thread looks at its stop flag when no frame arrives, ms: bounds how long
// stopReceiver() and the destructor wait.
constexpr std::chrono::milliseconds kReceiverPollInterval{20};

// Messages one drainSub() call reads at most, as a multiple of the SUB high-water mark: a server
// publishing faster than this client decodes cannot keep it in the loop for ever.
constexpr int kDrainHighWaterMarks = 4;

}  // namespace

std::optional<StateFrame> ClientSession::Impl::takeChunk(const std::uint8_t* data, std::size_t size) {
    StateFrame chunk = assembler.spare();
    if (!decodeStateFrameInto(data, size, chunk, frameLimits).ok()) {
        assembler.recycle(std::move(chunk));
        countMalformed();
        return std::nullopt;
    }
    std::optional<StateFrame> whole = assembler.add(std::move(chunk));
    std::lock_guard lock(m);
    syncAssemblerStats();
    return whole;
}

void ClientSession::Impl::syncAssemblerStats() {
    const AssemblerStats& a = assembler.stats();
    stats.framesReceived = a.delivered;
    stats.framesLost = a.lost;
    stats.staleChunks = a.stale;
    stats.inconsistentFrames = a.inconsistent;
    stats.sequenceRestarts = a.restarts;
}

std::optional<StateFrame> ClientSession::Impl::drainSub() {
    std::optional<StateFrame> newest;
    std::uint64_t chunks = 0, bytes = 0, bad = 0;
    const int most = kDrainHighWaterMarks * std::max(opt.frameHighWaterMark, 16);
    for (int k = 0; k < most; ++k) {
        // A frame message is [tier (1 byte), chunk]; ZeroMQ delivers the parts of a message together.
        zmq::message_t topic, chunk;
        if (!sub->recv(topic, zmq::recv_flags::dontwait)) break;
        bytes += topic.size();
        const bool twoParts = topic.more() && sub->recv(chunk, zmq::recv_flags::dontwait).has_value();
        bytes += chunk.size();
        bool extra = false;
        for (zmq::message_t part; chunk.more() && sub->recv(part, zmq::recv_flags::dontwait);) {
            bytes += part.size();
            chunk = std::move(part);
            extra = true;
        }
        if (!twoParts || extra || topic.size() != 1) {
            ++bad;
            continue;
        }
        ++chunks;
        if (auto whole = takeChunk(static_cast<const std::uint8_t*>(chunk.data()), chunk.size())) {
            if (newest) assembler.recycle(std::move(*newest));
            newest = std::move(whole);
        }
    }
    std::lock_guard lock(m);
    stats.chunksReceived += chunks;
    stats.bytesReceived += bytes;
    stats.malformed += bad;
    return newest;
}

std::optional<StateFrame> ClientSession::Impl::drainUdp() {
    if (!udpFrames) return std::nullopt;
    std::optional<StateFrame> newest;
    // A frame travels as one message of stream kFrameStream: the whole frame, one chunk.
    for (const Message& msg : udpFrames->receive(0)) {
        if (msg.stream != kUdpFrameStream) continue;
        if (auto whole = takeChunk(msg.bytes.data(), msg.bytes.size())) {
            if (newest) assembler.recycle(std::move(*newest));
            newest = std::move(whole);
        }
    }
    std::lock_guard lock(m);
    stats.udpDatagrams = udpFrames->datagrams();
    stats.udpFramesLost = udpFrames->stats().lost;
    return newest;
}

// Frames come over UDP when a UDP frame port is set (the SUB socket then subscribes to nothing),
// else over the SUB socket.
std::optional<StateFrame> ClientSession::Impl::drainFrames() {
    return udpFrames ? drainUdp() : drainSub();
}

std::optional<StateFrame> ClientSession::receiveFrame(std::chrono::milliseconds timeout) {
    Impl& d = *impl_;
    if (!d.sub) throw std::logic_error("ClientSession::receiveFrame before connect");
    if (d.running) throw std::logic_error("ClientSession::receiveFrame while the receiver thread runs");
    d.joinReceiver();  // one that stopped on an error gives the SUB socket back
    const auto deadline = Clock::now() + timeout;
    std::optional<StateFrame> newest;
    for (;;) {
        if (auto whole = d.drainFrames()) {
            if (newest) d.assembler.recycle(std::move(*newest));
            newest = std::move(whole);
        }
        if (newest || Clock::now() >= deadline) return newest;
        d.waitReadable(*d.sub, deadline, d.udpFrameFd());
    }
}

void ClientSession::Impl::receiverLoop() noexcept {
    try {
        while (!stopReceiver) {
            if (auto whole = drainFrames()) {
                std::shared_ptr<const StateFrame> frame = std::make_shared<StateFrame>(std::move(*whole));
                {
                    std::lock_guard lock(m);
                    std::swap(latest.frame, frame);
                    ++latest.count;
                }
                // The frame replaced, if no renderer still holds it: out of the slot, it cannot be
                // handed out again, so a count of one means it is ours alone (made non-const above).
                if (frame && frame.use_count() == 1) assembler.recycle(std::move(const_cast<StateFrame&>(*frame)));
            }
            waitReadable(*sub, Clock::now() + kReceiverPollInterval, udpFrameFd());
        }
    } catch (const std::exception& e) {  // a socket error or memory exhausted: stop, say why
        std::lock_guard lock(m);
        receiverError = e.what();
    } catch (...) {
        std::lock_guard lock(m);
        receiverError = "unknown exception in the frame receiver";
    }
    running = false;
}

void ClientSession::Impl::joinReceiver() {
    stopReceiver = true;
    if (receiver.joinable()) receiver.join();
    stopReceiver = false;
}

void ClientSession::startReceiver() {
    Impl& d = *impl_;
    if (!d.sub) throw std::logic_error("ClientSession::startReceiver before connect");
    if (d.running) return;
    d.joinReceiver();  // one that stopped on an error
    {
        std::lock_guard lock(d.m);
        d.receiverError.clear();
    }
    d.running = true;
    try {
        d.receiver = std::thread([&d] { d.receiverLoop(); });
    } catch (...) {
        d.running = false;
        throw;
    }
}

void ClientSession::recycle(StateFrame&& frame) {
    if (!impl_->running) impl_->assembler.recycle(std::move(frame));
}

void ClientSession::stopReceiver() {
    impl_->joinReceiver();
}

bool ClientSession::receiving() const {
    return impl_->running;
}

LatestFrame ClientSession::latestFrame() const {
    std::lock_guard lock(impl_->m);
    return impl_->latest;
}

std::string ClientSession::receiverError() const {
    std::lock_guard lock(impl_->m);
    return impl_->receiverError;
}

}  // namespace bop::protocol
