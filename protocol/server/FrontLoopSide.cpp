// The step loop's side of the front: the inbound slots and the frame slot, each under its own
// lock, never the sessions' and never a socket call (ServerFrontImpl.hpp).
#include "codec/MessageKind.hpp"
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <utility>

namespace bop::protocol {

using front::nowNs;
using Clock = front::Clock;

namespace {

// The step loop's hold on a slot's lock: taken at once when free; when one of the front's
// threads holds it, the wait is timed into the slot's LoopWaits (FrontStats::loopWait*), so that a
// run says how long its step loop ever waited on the front.
class LoopLock {
public:
    LoopLock(std::mutex& m, front::LoopWaits& waits) : m_(m) {
        if (m.try_lock()) return;
        const auto t0 = Clock::now();
        m.lock();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        ++waits.count;
        waits.totalMs += ms;
        waits.longestMs = std::max(waits.longestMs, ms);
    }
    ~LoopLock() { m_.unlock(); }
    LoopLock(const LoopLock&) = delete;
    LoopLock& operator=(const LoopLock&) = delete;

private:
    std::mutex& m_;
};

}  // namespace

std::vector<PendingCommand> ServerFront::takeCommands() {
    front::InboundSlots& in = impl_->inbound;
    LoopLock lock(in.m, in.waits);
    return std::exchange(in.commands, {});
}

std::optional<Probe> ServerFront::takeProbe() {
    front::InboundSlots& in = impl_->inbound;
    LoopLock lock(in.m, in.waits);
    return std::exchange(in.probe, std::nullopt);
}

bool ServerFront::frameDue(Clock::time_point now) {
    Impl& d = *impl_;
    if (now < d.nextTick) return false;
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / d.rateHz.load()));
    d.nextTick = std::max(d.nextTick + period, now);  // no burst after a pause
    return true;
}

void ServerFront::offerFrame(StateFrame frame) {
    front::FrameSlot& f = impl_->frames;
    LoopLock lock(f.m, f.waits);
    if (f.frame) ++f.dropped;
    f.frame = std::move(frame);
    f.offered.notify_one();
}

void ServerFront::offerEncodedFrame(std::vector<Buffer> chunks) {
    front::FrameSlot& f = impl_->frames;
    LoopLock lock(f.m, f.waits);
    if (f.encoded) ++f.dropped;
    f.encoded = std::move(chunks);
    f.offered.notify_one();
}

StateFrame ServerFront::takeSpareFrame() {
    front::FrameSlot& f = impl_->frames;
    LoopLock lock(f.m, f.waits);
    return std::exchange(f.spare, {});
}

bool ServerFront::framePending() const {
    front::FrameSlot& f = impl_->frames;
    LoopLock lock(f.m, f.waits);
    return f.frame.has_value() || f.encoded.has_value();
}

// The step loop's rare errors go to the sessions' count: the only time it takes their lock.
void ServerFront::loopError(const std::string& what) {
    std::lock_guard lock(impl_->m);
    impl_->internalError(what);
}

void ServerFront::offerFeedback(const Feedback& feedback) {
    if (const Validation v = validate(feedback); !v.ok()) return loopError("feedback not sent: " + v.message);
    {
        front::InboundSlots& in = impl_->inbound;
        LoopLock lock(in.m, in.waits);
        in.feedback = feedback;
    }
    impl_->wake();
}

void ServerFront::reply(const PendingCommand& command, const CommandReply& reply) {
    CommandReply r = reply;
    r.message.resize(std::min(r.message.size(), kMaxTextBytes));
    Buffer b, in;
    try {
        b = encodeCommandReply(r);
        in = encodeCommand(command.command);  // for the recording, if one runs
    } catch (const std::exception& e) {
        return loopError(std::string("reply not sent: ") + e.what());
    }
    {
        front::InboundSlots& slots = impl_->inbound;
        LoopLock lock(slots.m, slots.waits);
        slots.replies.emplace_back(command.client, b);
        if (impl_->recording) slots.toRecord.emplace_back(std::move(in), b);
    }
    impl_->wake();
}

void ServerFront::inject(const std::string& id, const std::uint8_t* data, std::size_t size) {
    std::lock_guard lock(impl_->m);
    impl_->handle(id, data, size, [] { return std::string("127.0.0.1"); });
    impl_->wake();
}

void ServerFront::probeApplied(const Probe& probe, std::uint64_t step) {
    if (!impl_->recording) return;
    std::pair<Buffer, Buffer> input;
    try {
        input = {encodeProbe(probe), encodeFeedback({probe.seq, step, {}, nowNs()})};
    } catch (const std::exception& e) {
        return loopError(std::string("probe not recorded: ") + e.what());
    }
    front::InboundSlots& in = impl_->inbound;
    LoopLock lock(in.m, in.waits);
    in.toRecord.push_back(std::move(input));
}

void ServerFront::startRecording(const std::string& path) {
    stopRecording();
    SceneInfo scene;
    {
        std::lock_guard lock(impl_->m);
        scene = impl_->sceneNow();
    }
    auto r = std::make_unique<SessionRecorder>(path, scene, impl_->opt.recordMeta);
    std::lock_guard recording(impl_->recordMutex);  // writers hold both locks, readers either
    std::lock_guard lock(impl_->m);
    impl_->recorder = std::move(r);
    impl_->recording = true;
}

std::string ServerFront::stopRecording() {
    std::unique_ptr<SessionRecorder> r;
    {
        std::lock_guard recording(impl_->recordMutex);
        std::vector<std::pair<Buffer, Buffer>> answered;  // inputs applied before the stop: this recording's
        {
            std::lock_guard lock(impl_->inbound.m);
            answered.swap(impl_->inbound.toRecord);
        }
        for (const auto& input : answered) impl_->recordInputLocked(input);
        std::lock_guard lock(impl_->m);
        r = std::move(impl_->recorder);
        impl_->recording = false;
    }
    if (!r) return {};
    const std::string path = r->path();
    r->close();
    return path;
}

void ServerFront::setParticleCount(std::uint64_t n) {
    impl_->particleCount = n;
}

void ServerFront::setMapEdits(std::shared_ptr<const std::vector<MapEdit>> edits) {
    front::InboundSlots& in = impl_->inbound;
    LoopLock lock(in.m, in.waits);
    in.mapEdits.swap(edits);  // the old list is let go after the lock
}

bool ServerFront::waitForClient(std::chrono::milliseconds timeout) {
    std::unique_lock lock(impl_->m);
    return impl_->helloSeen.wait_for(lock, timeout, [&] { return !impl_->clients.empty(); });
}

FrontStats ServerFront::stats() const {
    FrontStats s;
    {
        std::lock_guard lock(impl_->m);
        s = impl_->stats;
    }
    const auto addWaits = [&](const front::LoopWaits& w) {
        s.loopWaits += w.count;
        s.loopWaitTotalMs += w.totalMs;
        s.loopWaitLongestMs = std::max(s.loopWaitLongestMs, w.longestMs);
    };
    {
        std::lock_guard lock(impl_->inbound.m);
        addWaits(impl_->inbound.waits);
    }
    std::lock_guard lock(impl_->frames.m);
    addWaits(impl_->frames.waits);
    s.framesSent = impl_->frames.sent;
    s.framesDropped = impl_->frames.dropped;
    s.bytesSent = impl_->frames.bytes;
    s.publishError = impl_->frames.publishError;
    return s;
}

}  // namespace bop::protocol
