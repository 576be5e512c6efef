#include "server/ServerFront.hpp"

#include "bop/common/Error.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "server/FrontUdp.hpp"
#include "server/SessionRecorder.hpp"

#include <zmq.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>
#include <utility>

namespace bop::protocol {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kMaxInboundBytes = 64 * 1024;  // ZeroMQ drops larger messages and their peer
constexpr std::size_t kMaxQueuedCommands = 1024;     // beyond: refused as the step loop is behind
constexpr int kPubHighWaterMark = 64;                // messages queued per subscriber before PUB drops

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// Frames a client that wants `wantedHz` gets of a server publishing at `rateHz`: every 2^tier-th
// (docs/protocol.md, "Frame rate tiers").
int tierFor(float rateHz, float wantedHz) {
    if (!(wantedHz > 0) || wantedHz >= rateHz) return 0;
    return std::clamp(int(std::floor(std::log2(rateHz / wantedHz))), 0, 7);
}

struct Client {
    Role role = Role::Viewer;
    bool mayCommand = true;
    float wantedHz = 0;
    Clock::time_point lastProbe{};
};

}  // namespace

struct ServerFront::Impl {
    FrontOptions opt;
    SceneInfo scene;
    zmq::context_t ctx{1};
    zmq::socket_t router{ctx, zmq::socket_type::router}, pub{ctx, zmq::socket_type::pub};
    int controlPort = 0, framePort = 0;
    std::string controlEndpoint;
    std::atomic<bool> stop{false};
    std::thread thread;

    mutable std::mutex m;  // guards everything below
    std::condition_variable helloSeen;
    std::vector<PendingCommand> commands;
    std::optional<Probe> probe;
    std::optional<StateFrame> frame;
    std::optional<std::vector<Buffer>> encodedFrame;
    std::optional<Feedback> feedback;
    std::vector<std::pair<std::string, Buffer>> replies;
    std::vector<std::pair<Buffer, Buffer>> toRecord;  // (command, reply) or (probe, applied)
    std::unique_ptr<SessionRecorder> recorder;        // used by the thread only, once it runs
    std::unique_ptr<FrontUdp> udp;                    // the same
    std::map<std::string, Client> clients;
    FrontStats stats;
    std::atomic<float> rateHz{60};
    std::atomic<bool> haptic{false};
    std::uint64_t particleCount = 0;
    std::uint64_t frameNumber = 0;   // frames published (tier of the next one)
    Clock::time_point nextTick{};    // step loop's publish clock

    int bind(zmq::socket_t& s, int port) {
        const std::string ep = "tcp://" + opt.bindAddress + ":" + (opt.basePort == 0 ? std::string("*") : std::to_string(port));
        try {
            s.bind(ep);
        } catch (const zmq::error_t& e) {
            throw Error(ep, std::string("cannot bind: ") + e.what());
        }
        const std::string last = s.get(zmq::sockopt::last_endpoint);
        return std::stoi(last.substr(last.rfind(':') + 1));
    }

    void configure(zmq::socket_t& s) {
        s.set(zmq::sockopt::linger, 0);
        s.set(zmq::sockopt::maxmsgsize, std::int64_t(kMaxInboundBytes));
        if (!opt.curveSecretKey.empty()) {
            s.set(zmq::sockopt::curve_server, 1);
            s.set(zmq::sockopt::curve_secretkey, opt.curveSecretKey);
        }
    }

    void sendTo(const std::string& id, const Buffer& b) {
        // Never blocks: a peer that is gone or full loses the message.
        router.send(zmq::buffer(id), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
        router.send(zmq::buffer(b), zmq::send_flags::dontwait);
    }

    SceneInfo sceneNow() {
        SceneInfo s = scene;
        s.particleCount = particleCount;
        s.publishRateHz = rateHz.load();
        s.endpoints.frameEndpoint = "tcp://" + (opt.bindAddress == "*" ? std::string("127.0.0.1") : opt.bindAddress) + ":" +
                                    std::to_string(framePort);
        s.endpoints.udpProbePort = udp ? std::uint16_t(udp->port()) : 0;
        return s;
    }

    void refuse(const std::string& id, const Command& c, ReplyStatus status, const std::string& why) {
        CommandReply r;
        r.requestId = c.requestId;
        r.status = status;
        r.message = why;
        sendTo(id, encodeCommandReply(r));
    }

    // One inbound message from peer `id` (m held).
    void handle(const std::string& id, zmq::message_t& msg) {
        const auto* data = static_cast<const std::uint8_t*>(msg.data());
        const std::size_t size = msg.size();
        const auto bad = [&](DecodeError e) {
            ++stats.malformed;
            if (e == DecodeError::TooLarge) ++stats.oversized;
        };
        switch (messageKind(data, size)) {
        case MessageKind::Hello: {
            const auto h = decodeHello(data, size);
            if (!h) return bad(h.error);
            ++stats.hellos;
            Client& c = clients[id];
            c.role = h.value.role;
            c.wantedHz = h.value.frameRateHz;
            c.mayCommand = !h.value.readOnly && (opt.viewersMayCommand || h.value.role != Role::Viewer);
            float rate = opt.publishHz;
            for (const auto& [_, other] : clients) rate = std::max(rate, std::min(other.wantedHz, opt.maxPublishHz));
            rateHz = rate;
            stats.clients = clients.size();
            if (udp && h.value.udpFramePort) {
                std::string address = "127.0.0.1";
                try {
                    address = msg.gets("Peer-Address");
                } catch (const zmq::error_t&) {  // not a TCP peer: loopback
                }
                udp->setFrameClient(id, address, h.value.udpFramePort, tierFor(rate, c.wantedHz));
            }
            sendTo(id, encodeSceneInfo(sceneNow()));
            helloSeen.notify_all();
            return;
        }
        case MessageKind::Command: {
            const auto c = decodeCommand(data, size);
            if (!c) return bad(c.error);
            ++stats.commands;
            const auto it = clients.find(id);
            if (it == clients.end()) return refuse(id, c.value, ReplyStatus::Rejected, "hello first");
            if (!it->second.mayCommand) return refuse(id, c.value, ReplyStatus::ReadOnly, "this session is read-only");
            if (commands.size() >= kMaxQueuedCommands) return refuse(id, c.value, ReplyStatus::Rejected, "server busy");
            commands.push_back({id, true, c.value});
            return;
        }
        case MessageKind::Probe: {
            const auto p = decodeProbe(data, size);
            if (!p) return bad(p.error);
            const auto it = clients.find(id);
            if (it == clients.end()) return bad(DecodeError::None);  // probes need a session
            ++stats.probes;
            it->second.lastProbe = Clock::now();
            if (!probe || p.value.seq > probe->seq) probe = p.value;
            return;
        }
        default:
            return bad(DecodeError::WrongIdentifier);
        }
    }

    void publish(StateFrame f) {
        f.serverTimeNs = nowNs();
        f.encoding = opt.quantised ? FrameEncoding::Quantised16 : FrameEncoding::Float32;
        f.quantLo = scene.boxLo;
        f.quantHi = scene.boxHi;
        const std::vector<Buffer> chunks = encodeStateFrameChunks(f, opt.chunkBytes);
        send(chunks);
        if (udp) udp->frame(chunks.size() == 1 ? chunks.front() : encodeStateFrame(f), frameNumber);
    }

    void send(const std::vector<Buffer>& chunks) {
        const std::uint64_t n = ++frameNumber;
        const std::uint8_t tier = std::uint8_t(std::min(std::countr_zero(n), 7));
        std::size_t bytes = 0;
        for (const Buffer& chunk : chunks) {
            pub.send(zmq::buffer(&tier, 1), zmq::send_flags::sndmore | zmq::send_flags::dontwait);
            pub.send(zmq::buffer(chunk), zmq::send_flags::dontwait);  // PUB drops for a full subscriber
            bytes += chunk.size();
            record([&] { recorder->frameChunk(chunk); });
        }
        std::lock_guard lock(m);
        ++stats.framesSent;
        stats.bytesSent += bytes;
    }

    // Runs a recorder call; a failure (disk full, ...) ends the recording, never the server.
    template <class F> void record(F f) {
        if (!recorder) return;
        try {
            f();
        } catch (const std::exception& e) {
            std::lock_guard lock(m);
            stats.recordError = e.what();
            recorder.reset();
        }
    }

    void loop() {
        zmq::pollitem_t items[] = {{router.handle(), 0, ZMQ_POLLIN, 0}};
        while (!stop) {
            zmq::poll(items, 1, std::chrono::milliseconds(1));
            std::optional<StateFrame> f;
            std::optional<std::vector<Buffer>> encoded;
            std::optional<Feedback> fb;
            std::vector<std::pair<Buffer, Buffer>> inputs;
            {
                std::lock_guard lock(m);
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
                    if (!parts) { ++stats.malformed; continue; }
                    handle(id.to_string(), body);
                }
                for (auto& [id, b] : replies) sendTo(id, b);
                replies.clear();
                f.swap(frame);
                encoded.swap(encodedFrame);
                fb.swap(feedback);
                inputs.swap(toRecord);
                if (udp) {
                    const FrontUdp::Inbound in = udp->poll(Clock::now());
                    stats.probes += in.probes;
                    stats.malformed += in.malformed;
                    stats.oversized += in.oversized;
                    if (in.newest && (!probe || in.newest->seq > probe->seq)) probe = in.newest;
                }
                if (fb) {
                    const Buffer b = encodeFeedback(*fb);
                    const auto recent = Clock::now() - std::chrono::seconds(1);
                    bool any = false;
                    for (const auto& [id, c] : clients)
                        if (c.lastProbe > recent) sendTo(id, b), any = true;
                    if (udp) udp->feedback(b, Clock::now()), any = any || udp->anyProbing(Clock::now());
                    haptic = any;
                }
            }
            for (const auto& [a, b] : inputs)
                record([&] { messageKind(a.data(), a.size()) == MessageKind::Command ? recorder->command(a, b) : recorder->probe(a, b); });
            if (f) publish(std::move(*f));
            if (encoded) send(*encoded);
        }
    }
};

ServerFront::ServerFront(FrontOptions options, SceneInfo scene) : impl_(std::make_unique<Impl>()) {
    Impl& d = *impl_;
    d.opt = std::move(options);
    d.scene = std::move(scene);
    d.rateHz = d.opt.publishHz;
    d.configure(d.router);
    d.configure(d.pub);
    d.pub.set(zmq::sockopt::sndhwm, kPubHighWaterMark);
    d.controlPort = d.bind(d.router, d.opt.basePort);
    d.framePort = d.bind(d.pub, d.opt.basePort + 1);
    if (d.opt.udp) d.udp = std::make_unique<FrontUdp>(d.opt.bindAddress, d.opt.basePort == 0 ? 0 : d.opt.basePort + 2);
    d.controlEndpoint = "tcp://" + (d.opt.bindAddress == "*" ? std::string("127.0.0.1") : d.opt.bindAddress) + ":" +
                        std::to_string(d.controlPort);
    if (!d.opt.recordPath.empty()) d.recorder = std::make_unique<SessionRecorder>(d.opt.recordPath, d.sceneNow(), d.opt.recordMeta);
    d.thread = std::thread([&d] { d.loop(); });
}

void ServerFront::finish() {
    impl_->stop = true;
    if (impl_->thread.joinable()) impl_->thread.join();
    if (impl_->recorder) {
        auto r = std::move(impl_->recorder);
        r->close();
    }
}

ServerFront::~ServerFront() {
    try {
        finish();
    } catch (...) {  // the file keeps its .partial name; finish() reported the error to whoever called it
    }
}

int ServerFront::controlPort() const { return impl_->controlPort; }
int ServerFront::framePort() const { return impl_->framePort; }
int ServerFront::udpProbePort() const { return impl_->udp ? impl_->udp->port() : 0; }
std::string ServerFront::controlEndpoint() const { return impl_->controlEndpoint; }
float ServerFront::publishHz() const { return impl_->rateHz.load(); }
bool ServerFront::anyHaptic() const { return impl_->haptic.load(); }

std::vector<PendingCommand> ServerFront::takeCommands() {
    std::lock_guard lock(impl_->m);
    return std::exchange(impl_->commands, {});
}

std::optional<Probe> ServerFront::takeProbe() {
    std::lock_guard lock(impl_->m);
    return std::exchange(impl_->probe, std::nullopt);
}

bool ServerFront::frameDue(Clock::time_point now) {
    Impl& d = *impl_;
    if (now < d.nextTick) return false;
    const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / d.rateHz.load()));
    d.nextTick = std::max(d.nextTick + period, now);  // no burst after a pause
    return true;
}

void ServerFront::offerFrame(StateFrame frame) {
    std::lock_guard lock(impl_->m);
    if (impl_->frame) ++impl_->stats.framesDropped;
    impl_->frame = std::move(frame);
}

void ServerFront::offerEncodedFrame(std::vector<Buffer> chunks) {
    std::lock_guard lock(impl_->m);
    if (impl_->encodedFrame) ++impl_->stats.framesDropped;
    impl_->encodedFrame = std::move(chunks);
}

void ServerFront::offerFeedback(const Feedback& feedback) {
    std::lock_guard lock(impl_->m);
    impl_->feedback = feedback;
}

void ServerFront::reply(const PendingCommand& command, const CommandReply& reply) {
    const Buffer b = encodeCommandReply(reply);
    std::lock_guard lock(impl_->m);
    impl_->replies.emplace_back(command.client, b);
    if (impl_->recorder) impl_->toRecord.emplace_back(encodeCommand(command.command), b);
}

void ServerFront::probeApplied(const Probe& probe, std::uint64_t step) {
    std::lock_guard lock(impl_->m);
    if (impl_->recorder) impl_->toRecord.emplace_back(encodeProbe(probe), encodeFeedback({probe.seq, step, {}, nowNs()}));
}

void ServerFront::setParticleCount(std::uint64_t n) {
    std::lock_guard lock(impl_->m);
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
