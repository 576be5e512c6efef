// The step loop's side of the front: slots guarded by the front's mutex, never a socket call.
#include "codec/MessageKind.hpp"
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <utility>

namespace bop::protocol {

using front::nowNs;
using Clock = front::Clock;

namespace {

// The step loop's hold on the front's mutex: taken at once when free; when one of the front's
// threads holds it, the wait is timed into FrontStats (loopWait*), so that a run says how long
// its step loop ever waited on the front.
class LoopLock {
public:
    LoopLock(std::mutex& m, FrontStats& stats) : m_(m) {
        if (m.try_lock()) return;
        const auto t0 = Clock::now();
        m.lock();
        const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        ++stats.loopWaits;
        stats.loopWaitTotalMs += ms;
        stats.loopWaitLongestMs = std::max(stats.loopWaitLongestMs, ms);
    }
    ~LoopLock() { m_.unlock(); }
    LoopLock(const LoopLock&) = delete;
    LoopLock& operator=(const LoopLock&) = delete;

private:
    std::mutex& m_;
};

}  // namespace

std::vector<PendingCommand> ServerFront::takeCommands() {
    LoopLock lock(impl_->m, impl_->stats);
    return std::exchange(impl_->commands, {});
}

std::optional<Probe> ServerFront::takeProbe() {
    LoopLock lock(impl_->m, impl_->stats);
    return std::exchange(impl_->probe, std::nullopt);
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
    LoopLock lock(impl_->m, impl_->stats);
    if (impl_->frame) ++impl_->stats.framesDropped;
    impl_->frame = std::move(frame);
    impl_->frameOffered.notify_one();
}

void ServerFront::offerEncodedFrame(std::vector<Buffer> chunks) {
    LoopLock lock(impl_->m, impl_->stats);
    if (impl_->encodedFrame) ++impl_->stats.framesDropped;
    impl_->encodedFrame = std::move(chunks);
    impl_->frameOffered.notify_one();
}

StateFrame ServerFront::takeSpareFrame() {
    LoopLock lock(impl_->m, impl_->stats);
    return std::exchange(impl_->spareFrame, {});
}

bool ServerFront::framePending() const {
    LoopLock lock(impl_->m, impl_->stats);
    return impl_->frame.has_value() || impl_->encodedFrame.has_value();
}

void ServerFront::offerFeedback(const Feedback& feedback) {
    const Validation v = validate(feedback);
    LoopLock lock(impl_->m, impl_->stats);
    if (!v.ok()) return impl_->internalError("feedback not sent: " + v.message);
    impl_->feedback = feedback;
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
        LoopLock lock(impl_->m, impl_->stats);
        return impl_->internalError(std::string("reply not sent: ") + e.what());
    }
    LoopLock lock(impl_->m, impl_->stats);
    impl_->replies.emplace_back(command.client, b);
    if (impl_->recorder) impl_->toRecord.emplace_back(std::move(in), b);
    impl_->wake();
}

void ServerFront::inject(const std::string& id, const std::uint8_t* data, std::size_t size) {
    std::lock_guard lock(impl_->m);
    impl_->handle(id, data, size, [] { return std::string("127.0.0.1"); });
    impl_->wake();
}

void ServerFront::probeApplied(const Probe& probe, std::uint64_t step) {
    LoopLock lock(impl_->m, impl_->stats);
    if (!impl_->recorder) return;
    try {
        impl_->toRecord.emplace_back(encodeProbe(probe), encodeFeedback({probe.seq, step, {}, nowNs()}));
    } catch (const std::exception& e) {
        impl_->internalError(std::string("probe not recorded: ") + e.what());
    }
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
}

std::string ServerFront::stopRecording() {
    std::unique_ptr<SessionRecorder> r;
    {
        std::lock_guard recording(impl_->recordMutex);
        std::vector<std::pair<Buffer, Buffer>> answered;  // inputs applied before the stop: this recording's
        {
            std::lock_guard lock(impl_->m);
            answered.swap(impl_->toRecord);
        }
        for (const auto& input : answered) impl_->recordInputLocked(input);
        std::lock_guard lock(impl_->m);
        r = std::move(impl_->recorder);
    }
    if (!r) return {};
    const std::string path = r->path();
    r->close();
    return path;
}

void ServerFront::setParticleCount(std::uint64_t n) {
    LoopLock lock(impl_->m, impl_->stats);
    impl_->particleCount = n;
}

bool ServerFront::waitForClient(std::chrono::milliseconds timeout) {
    std::unique_lock lock(impl_->m);
    return impl_->helloSeen.wait_for(lock, timeout, [&] { return !impl_->clients.empty(); });
}

FrontStats ServerFront::stats() const {
    std::lock_guard lock(impl_->m);
    return impl_->stats;
}

}  // namespace bop::protocol
