#include "bop/common/Error.hpp"
#include "codec/MessageKind.hpp"
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <thread>

#include <sys/eventfd.h>
#include <unistd.h>

namespace bop::protocol {
namespace {

using front::kMaxInboundBytes;
using front::kMaxQueuedCommands;
using front::kPubHighWaterMark;
using front::nowNs;
using Clock = front::Clock;

}  // namespace

int ServerFront::Impl::bind(zmq::socket_t& s, int port) {
    const std::string ep =
        "tcp://" + opt.bindAddress + ":" + (opt.basePort == 0 ? std::string("*") : std::to_string(port));
    try {
        s.bind(ep);
    } catch (const zmq::error_t& e) {
        throw Error(ep, std::string("cannot bind: ") + e.what());
    }
    const std::string last = s.get(zmq::sockopt::last_endpoint);
    return std::stoi(last.substr(last.rfind(':') + 1));
}

void ServerFront::Impl::configure(zmq::socket_t& s) {
    s.set(zmq::sockopt::linger, 0);
    s.set(zmq::sockopt::maxmsgsize, std::int64_t(kMaxInboundBytes));
    if (!opt.curveSecretKey.empty()) {
        s.set(zmq::sockopt::curve_server, 1);
        s.set(zmq::sockopt::curve_secretkey, opt.curveSecretKey);
    }
}

void ServerFront::Impl::sendTo(const std::string& id, const Buffer& b) {
    // Never blocks: a peer that is gone or full loses the message.
    router.send(zmq::buffer(id), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
    router.send(zmq::buffer(b), zmq::send_flags::dontwait);
}

SceneInfo ServerFront::Impl::sceneNow() {
    SceneInfo s = scene;
    s.particleCount = particleCount;
    s.publishRateHz = rateHz.load();
    s.endpoints.frameEndpoint = "tcp://" + (opt.bindAddress == "*" ? std::string("127.0.0.1") : opt.bindAddress) + ":" +
                                std::to_string(framePort);
    s.endpoints.udpProbePort = udp ? std::uint16_t(udp->port()) : 0;
    s.sessionTimeoutS = float(std::chrono::duration<double>(opt.sessionTimeout).count());
    return s;
}

void ServerFront::Impl::loop() {
    // Probes over TCP or UDP, the step loop's offers and handshakes to authenticate all wake the
    // thread at once.
    std::vector<zmq::pollitem_t> items = {{router.handle(), 0, ZMQ_POLLIN, 0}, {nullptr, wakeFd, ZMQ_POLLIN, 0}};
    if (udp) items.push_back({nullptr, udp->fd(), ZMQ_POLLIN, 0});
    if (zap) items.push_back({zap->socket().handle(), 0, ZMQ_POLLIN, 0});
    while (!stop) {
        try {  // nothing thrown ends the thread: it is counted, said sparingly, and the loop goes on
            pass(items);
        } catch (const std::exception& e) {
            {
                std::lock_guard lock(m);
                internalError(e.what());
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a fault that repeats does not spin
        }
    }
}

void ServerFront::Impl::pass(std::vector<zmq::pollitem_t>& items) {
    try {
        zmq::poll(items, std::chrono::milliseconds(1));
    } catch (const zmq::error_t& e) {
        if (e.num() == EINTR) return;  // a signal: nothing wrong
        throw;
    }
    if (zap) {
        const std::uint64_t refused = zap->serve();
        std::lock_guard lock(m);
        stats.peersRefused += refused;
    }
    if (items[1].revents & ZMQ_POLLIN) {
        std::uint64_t n;
        [[maybe_unused]] const auto r = read(wakeFd, &n, sizeof n);  // clears the count
    }
    std::optional<Feedback> fb;
    std::vector<std::pair<Buffer, Buffer>> inputs;
    // The inputs taken for the recording are recorded however the rest of the pass goes: a
    // recording without an applied command would not replay.
    struct RecordOnExit {
        Impl& d;
        std::vector<std::pair<Buffer, Buffer>>& inputs;
        ~RecordOnExit() {
            std::lock_guard recording(d.recordMutex);
            for (const auto& input : inputs) d.recordInputLocked(input);
        }
    } recordOnExit{*this, inputs};
    std::vector<std::pair<std::string, Buffer>> out;
    {
        std::lock_guard lock(m);
        mapPiecesThisPass = 0;
        for (int k = 0; k < 256; ++k) {  // a burst, then the outbound side gets its turn
            zmq::message_t id, body;
            if (!router.recv(id, zmq::recv_flags::dontwait)) break;
            bool parts = id.more() && router.recv(body, zmq::recv_flags::dontwait).has_value();
            while (body.more()) {  // extra parts: not our protocol; drain them
                zmq::message_t extra;
                if (!router.recv(extra, zmq::recv_flags::dontwait)) break;
                parts = false;
                body = std::move(extra);
            }
            if (!parts) {
                ++stats.malformed;
                continue;
            }
            handle(id.to_string(), static_cast<const std::uint8_t*>(body.data()), body.size(), [&body] {
                try {
                    return std::string(body.gets("Peer-Address"));
                } catch (const zmq::error_t&) {  // not a TCP peer: loopback
                    return std::string("127.0.0.1");
                }
            });
        }
        const Clock::time_point now = Clock::now();
        if (now >= nextExpiry) expire(now), nextExpiry = now + std::chrono::milliseconds(100);
        out.swap(outbox);
        std::optional<Probe> newest;
        if (udp) {
            const FrontUdp::Inbound in = udp->poll(now, scene);
            stats.probes += in.probes;
            stats.malformed += in.malformed;
            stats.oversized += in.oversized;
            stats.outOfRange += in.outOfRange;
            stats.refusalsSent += in.refusalsSent;
            newest = in.newest;
        }
        {
            std::lock_guard slots(inbound.m);
            for (auto& r : inbound.replies) out.push_back(std::move(r));
            inbound.replies.clear();
            fb.swap(inbound.feedback);
            inputs.swap(inbound.toRecord);
            if (newest && (!inbound.probe || newest->seq > inbound.probe->seq)) inbound.probe = newest;
        }
        if (fb) {
            const Buffer b = encodeFeedback(*fb);  // finite: offerFeedback() let no other in
            const auto recent = now - std::chrono::seconds(1);
            bool any = false;
            for (const auto& [id, c] : clients)
                if (c.lastProbe > recent) out.emplace_back(id, b), any = true;
            if (udp) udp->feedback(b, now), any = any || udp->anyProbing(now);
            haptic = any;
        }
    }
    for (const auto& [id, b] : out) sendTo(id, b);
}

void ServerFront::Impl::recordInputLocked(const std::pair<Buffer, Buffer>& input) {
    recordLocked([&] {
        const Buffer& in = input.first;
        messageKind(in.data(), in.size()) == MessageKind::Command ? recorder->command(in, input.second)
                                                                  : recorder->probe(in, input.second);
    });
}

ServerFront::ServerFront(FrontOptions options, SceneInfo scene) : impl_(std::make_unique<Impl>()) {
    Impl& d = *impl_;
    d.opt = std::move(options);
    d.scene = std::move(scene);
    d.particleCount = d.scene.particleCount;
    d.rateHz = d.opt.publishHz;
    if (!d.opt.curveClientKeys.empty()) {
        if (d.opt.curveSecretKey.empty())
            throw Error("CURVE client keys", "a list of client keys needs the server's CURVE secret key");
        d.zap = std::make_unique<ZapHandler>(d.ctx, d.opt.curveClientKeys);  // before any CURVE socket binds
    }
    d.configure(d.router);
    d.configure(d.pub);
    d.pub.set(zmq::sockopt::sndhwm, kPubHighWaterMark);
    d.controlPort = d.bind(d.router, d.opt.basePort);
    d.framePort = d.bind(d.pub, d.opt.basePort + 1);
    // Datagrams are neither authenticated nor encrypted: with CURVE on, everything goes over it.
    if (d.opt.udp && d.opt.curveSecretKey.empty())
        d.udp = std::make_unique<FrontUdp>(d.opt.bindAddress, d.opt.basePort == 0 ? 0 : d.opt.basePort + 2);
    d.controlEndpoint = "tcp://" + (d.opt.bindAddress == "*" ? std::string("127.0.0.1") : d.opt.bindAddress) + ":" +
                        std::to_string(d.controlPort);
    if (!d.opt.recordPath.empty()) {
        d.recorder = std::make_unique<SessionRecorder>(d.opt.recordPath, d.sceneNow(), d.opt.recordMeta);
        d.recording = true;
    }
    d.wakeFd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (d.wakeFd < 0) throw Error("bop-server", std::string("eventfd: ") + std::strerror(errno));
    d.thread = std::thread([&d] { d.loop(); });
    d.publisher = std::thread([&d] { d.publisherLoop(); });
}

void ServerFront::Impl::wake() {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto r = write(wakeFd, &one, sizeof one);  // a full counter is still a wake-up
}

void ServerFront::finish() {
    impl_->stop = true;
    {
        std::lock_guard lock(impl_->frames.m);  // so that the publisher cannot miss it
        impl_->frames.stop = true;
    }
    impl_->frames.offered.notify_all();
    if (impl_->thread.joinable()) impl_->thread.join();
    if (impl_->publisher.joinable()) impl_->publisher.join();
    if (impl_->recorder) {
        auto r = std::move(impl_->recorder);
        impl_->recording = false;
        r->close();
    }
}

ServerFront::~ServerFront() {
    try {
        finish();
    } catch (...) {  // the file keeps its .partial name; finish() reported the error to whoever called it
    }
    if (impl_->wakeFd >= 0) close(impl_->wakeFd);
}

int ServerFront::controlPort() const {
    return impl_->controlPort;
}
int ServerFront::framePort() const {
    return impl_->framePort;
}
int ServerFront::udpProbePort() const {
    return impl_->udp ? impl_->udp->port() : 0;
}
std::string ServerFront::controlEndpoint() const {
    return impl_->controlEndpoint;
}
float ServerFront::publishHz() const {
    return impl_->rateHz.load();
}
bool ServerFront::anyHaptic() const {
    return impl_->haptic.load();
}

}  // namespace bop::protocol
