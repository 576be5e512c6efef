// The front's publisher (ServerFrontImpl.hpp): the frame slot the step loop offers to, emptied by
// the publisher thread, which encodes each frame into pooled chunks and hands them to the PUB
// socket (and UDP clients) without a copy. Its counts are kept in the slot, under its lock.
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <bit>

namespace bop::protocol {

using front::nowNs;

void ServerFront::Impl::publish(StateFrame f) {
    f.serverTimeNs = nowNs();
    f.frameSeq = frameNumber + 1;  // the number send() gives it
    if (!opt.frameIds) f.ids.clear();
    f.encoding = opt.frameEncoding;
    f.quantLo = scene.boxLo;
    f.quantHi = scene.boxHi;
    std::vector<Buffer> chunks = encodeStateFrameChunks(f, opt.chunkBytes, chunkPool.get());
    if (udp && udp->wantsFrame(frameNumber + 1))  // one message: the whole frame
        udp->frame(chunks.size() == 1 ? chunks.front() : encodeStateFrame(f), frameNumber + 1);
    send(std::move(chunks));
    std::lock_guard lock(frames.m);
    frames.spare = std::move(f);
}

namespace {

// A chunk handed to ZeroMQ without a copy; ZeroMQ frees it once every subscriber's copy is out
// (from its I/O thread, possibly after the front is gone: the pool is held weakly).
struct HeldChunk {
    Buffer bytes;
    std::weak_ptr<BufferPool> pool;
};

void releaseChunk(void*, void* hint) {
    std::unique_ptr<HeldChunk> held(static_cast<HeldChunk*>(hint));
    if (const auto pool = held->pool.lock()) pool->give(std::move(held->bytes));
}

}  // namespace

void ServerFront::Impl::send(std::vector<Buffer> chunks) {
    const std::uint64_t n = ++frameNumber;
    const std::uint8_t tier = std::uint8_t(std::min(std::countr_zero(n), 7));
    std::size_t bytes = 0;
    {
        std::lock_guard recording(recordMutex);  // a recording starts and stops between whole frames
        for (const Buffer& chunk : chunks) recordLocked([&] { recorder->frameChunk(chunk); });
    }
    for (Buffer& chunk : chunks) {
        bytes += chunk.size();
        auto held = std::make_unique<HeldChunk>(HeldChunk{std::move(chunk), chunkPool});
        zmq::message_t msg(held->bytes.data(), held->bytes.size(), releaseChunk, held.get());
        held.release();  // the message owns it now
        pub.send(zmq::buffer(&tier, 1), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
        pub.send(msg, zmq::send_flags::dontwait);  // PUB drops for a full subscriber
    }
    std::lock_guard lock(frames.m);
    ++frames.sent;
    frames.bytes += bytes;
}

void ServerFront::Impl::publisherLoop() {
    for (;;) {
        std::optional<StateFrame> f;
        std::optional<std::vector<Buffer>> encoded;
        {
            std::unique_lock lock(frames.m);
            frames.offered.wait(lock, [&] { return frames.stop || frames.frame || frames.encoded; });
            // A frame offered just before the stop is still sent (and recorded): a replay
            // compares every frame, the last one too.
            if (frames.stop && !frames.frame && !frames.encoded) return;
            f.swap(frames.frame);
            encoded.swap(frames.encoded);
        }
        try {
            if (f) publish(std::move(*f));
            if (encoded) send(std::move(*encoded));
        } catch (const std::exception& e) {  // a frame that cannot be encoded: not sent, the thread goes on
            {
                std::lock_guard lock(frames.m);
                ++frames.dropped;
                frames.publishError = e.what();
            }
            std::lock_guard lock(m);
            internalError(std::string("publishing a frame: ") + e.what());
        }
    }
}

}  // namespace bop::protocol
