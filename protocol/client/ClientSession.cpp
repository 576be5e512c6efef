#include "bop/common/Error.hpp"
#include "client/ClientSessionImpl.hpp"
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"
#include "security/CurveKeys.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <poll.h>

namespace bop::protocol {
namespace {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

std::string inMs(milliseconds t) {
    return std::to_string(t.count()) + " ms";
}

// "tcp://HOST:PORT" -> HOST; empty for anything else.
std::string tcpHost(const std::string& endpoint) {
    const std::size_t colon = endpoint.rfind(':');
    if (!endpoint.starts_with("tcp://") || colon == std::string::npos || colon < 6) return {};
    return endpoint.substr(6, colon - 6);
}

bool isLocalHost(const std::string& host) {
    return host == "127.0.0.1" || host == "localhost" || host == "::1" || host == "[::1]" || host == "*" ||
           host == "0.0.0.0";
}

// A server bound to every interface announces its frame endpoint on 127.0.0.1 (ServerFront),
// which seen from another machine is the client itself: keep the announced port, and use the
// host that reached the control endpoint.
std::string frameEndpointFor(const std::string& control, const std::string& announced) {
    const std::string controlHost = tcpHost(control), frameHost = tcpHost(announced);
    if (controlHost.empty() || frameHost.empty() || !isLocalHost(frameHost) || isLocalHost(controlHost))
        return announced;
    return "tcp://" + controlHost + announced.substr(announced.rfind(':'));
}

void requireKey(const std::string& key, const char* what) {
    if (!isCurveKey(key)) throw Error(what, "not a z85 CURVE key (40 characters)");
}

}  // namespace

int frameTierFor(float publishHz, float wantedHz) {
    if (!(publishHz > 0) || !(wantedHz > 0) || wantedHz >= publishHz) return 0;
    return std::clamp(int(std::floor(std::log2(double(publishHz) / double(wantedHz)))), 0, 7);
}

bool ClientSession::Impl::waitReadable(zmq::socket_t& s, Clock::time_point deadline, int fd) {
    const auto left = std::chrono::ceil<milliseconds>(deadline - Clock::now());
    if (left.count() <= 0) return false;
    zmq::pollitem_t items[] = {{s.handle(), 0, ZMQ_POLLIN, 0}, {nullptr, fd, ZMQ_POLLIN, 0}};
    try {
        return zmq::poll(items, fd >= 0 ? 2 : 1, left) > 0;
    } catch (const zmq::error_t& e) {
        if (e.num() == EINTR) return false;
        throw;
    }
}

void ClientSession::Impl::countMalformed() {
    std::lock_guard lock(m);
    ++stats.malformed;
}

void ClientSession::Impl::setCommonOptions(zmq::socket_t& s, std::size_t maxMessageBytes) {
    s.set(zmq::sockopt::linger, 0);  // closing never waits for unsent probes or commands
    s.set(zmq::sockopt::maxmsgsize, std::int64_t(maxMessageBytes));
    if (opt.curveServerKey.empty()) return;
    s.set(zmq::sockopt::curve_serverkey, opt.curveServerKey);
    s.set(zmq::sockopt::curve_publickey, opt.curvePublicKey);
    s.set(zmq::sockopt::curve_secretkey, opt.curveSecretKey);
}

MessageKind ClientSession::Impl::takeControl(const zmq::message_t& msg, CommandReply* reply) {
    const auto* data = static_cast<const std::uint8_t*>(msg.data());
    const std::size_t size = msg.size();
    const MessageKind kind = messageKind(data, size);
    bool ok = false;
    if (kind == MessageKind::SceneInfo) {
        auto s = decodeSceneInfo(data, size);
        if ((ok = s.ok())) scene = std::move(s.value);
    } else if (kind == MessageKind::Feedback) {
        const auto f = decodeFeedback(data, size);
        if ((ok = f.ok())) feedback = f.value;  // one TCP stream: the last to arrive is the newest
    } else if (kind == MessageKind::MapEdits) {
        auto e = decodeMapEdits(data, size);
        if ((ok = e.ok())) mapEdits = std::move(e.value);
    } else if (kind == MessageKind::Refusal) {
        auto r = decodeRefusal(data, size);
        if ((ok = r.ok())) takeRefusal(std::move(r.value));
    } else if (kind == MessageKind::CommandReply) {
        auto r = decodeCommandReply(data, size);
        if ((ok = r.ok()) && reply) *reply = std::move(r.value);
        if (ok && !reply) {
            std::lock_guard lock(m);
            ++stats.repliesDropped;
        }
    }
    if (!ok) countMalformed();
    return ok ? kind : MessageKind::Unknown;
}

void ClientSession::Impl::takeRefusal(Refusal r) {
    std::lock_guard lock(m);
    ++stats.refusals;
    stats.lastRefusal = r.kind + (r.seq ? " " + std::to_string(r.seq) : std::string()) + ": " + r.reason;
    refusal = std::move(r);
}

void ClientSession::Impl::send(const Buffer& b, const char* what) {
    if (!dealer->send(zmq::buffer(b), zmq::send_flags::dontwait))
        throw Error(controlEndpoint, std::string("cannot queue ") + what + " (send queue full)");
    lastSent = Clock::now();
}

void ClientSession::Impl::keepAlive() {
    if (!(scene.sessionTimeoutS > 0) || hello.empty()) return;
    const auto third = std::chrono::duration<double>(scene.sessionTimeoutS / 3.0);
    if (Clock::now() - lastSent < third) return;
    if (!dealer->send(zmq::buffer(hello), zmq::send_flags::dontwait)) return;  // full: the next poll tries again
    lastSent = Clock::now();
    std::lock_guard lock(m);
    ++stats.keepAlives;
}

void ClientSession::Impl::connectSub() {
    sub.emplace(ctx, zmq::socket_type::sub);
    setCommonOptions(*sub, opt.maxFrameChunkBytes);
    sub->set(zmq::sockopt::rcvhwm, opt.frameHighWaterMark);
    // Frames come over UDP instead when a UDP frame port is set: the SUB socket stays unsubscribed.
    for (int t = tier; t <= 7 && !udpFrames; ++t) {  // topic: one byte, the frame's tier
        const char topic = char(t);
        sub->set(zmq::sockopt::subscribe, std::string_view(&topic, 1));
    }
    try {
        sub->connect(frameEndpoint);
    } catch (const zmq::error_t& e) {
        throw Error(frameEndpoint, std::string("cannot connect the frame socket: ") + e.what());
    }
    frameLimits.maxChunkBytes = opt.maxFrameChunkBytes;
    frameLimits.speciesCount = int(scene.species.size());
}

ClientSession::ClientSession(ClientOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}

ClientSession::~ClientSession() {
    impl_->joinReceiver();
}

SceneInfo ClientSession::connect(const std::string& endpoint) {
    return connect(endpoint, impl_->opt.receiveTimeout);
}

SceneInfo ClientSession::connect(const std::string& endpoint, milliseconds timeout) {
    Impl& d = *impl_;
    if (!d.opt.curveServerKey.empty()) {
        requireKey(d.opt.curveServerKey, "CURVE server key");
        if (d.opt.curvePublicKey.empty() && d.opt.curveSecretKey.empty()) {
            const CurveKeyPair pair = makeCurveKeyPair();  // this session's own, unauthenticated
            d.opt.curvePublicKey = pair.publicKey;
            d.opt.curveSecretKey = pair.secretKey;
        }
        requireKey(d.opt.curvePublicKey, "CURVE client public key");
        requireKey(d.opt.curveSecretKey, "CURVE client secret key");
    }
    d.joinReceiver();
    d.sub.reset();
    d.dealer.reset();
    d.assembler.reset();  // a new session may number its frames from 1 again
    d.feedback.reset();
    d.refusal.reset();
    d.probeSocket.reset();
    d.udpFrames.reset();
    d.controlEndpoint = endpoint;
    try {
        d.dealer.emplace(d.ctx, zmq::socket_type::dealer);
        d.setCommonOptions(*d.dealer, d.opt.maxControlBytes);
        try {
            d.dealer->connect(endpoint);
        } catch (const zmq::error_t& e) {
            throw Error(endpoint, std::string("cannot connect: ") + e.what());
        }
        Hello hello;
        hello.role = d.opt.role;
        hello.frameRateHz = d.opt.frameRateHz;
        hello.readOnly = d.opt.readOnly;
        hello.clientName = d.opt.clientName;
        // Datagram sockets bind where the server is reached from: loopback for a local server.
        const std::string host = tcpHost(endpoint);
        const std::string udpLocal = isLocalHost(host) ? "127.0.0.1" : "0.0.0.0";
        if (d.opt.udpFramePort != 0) {
            d.udpFrames.emplace(UdpSocket(udpLocal, d.opt.udpFramePort));
            hello.udpFramePort = d.opt.udpFramePort;
        }
        d.hello = encodeHello(hello);  // EncodeError on a bad option (a name over 64 bytes, ...)
        d.send(d.hello, "Hello");
        const bool got = d.pumpControl(Clock::now() + timeout, [&](const zmq::message_t& msg) {
            const MessageKind k = d.takeControl(msg, nullptr);
            return k == MessageKind::SceneInfo || (k == MessageKind::Refusal && d.refusal->kind == "Hello");
        });
        if (d.refusal && d.refusal->kind == "Hello")
            throw Error(endpoint, "the server refused our Hello: " + d.refusal->reason);
        if (!got)
            throw Error(endpoint, "no SceneInfo within " + inMs(timeout) +
                                      (d.opt.curveServerKey.empty()
                                           ? std::string(" (is a bop-server listening there?)")
                                           : " (is a bop-server listening there, with the secret key matching our "
                                             "CURVE server key?)"));
        if (d.scene.endpoints.frameEndpoint.empty()) throw Error(endpoint, "SceneInfo announces no frame endpoint");
        d.tier = frameTierFor(d.scene.publishRateHz, d.opt.frameRateHz);
        d.frameEndpoint = frameEndpointFor(endpoint, d.scene.endpoints.frameEndpoint);
        if (d.opt.probeOverUdp) {
            if (d.scene.endpoints.udpProbePort == 0)
                throw Error(endpoint, "the server takes no probes over UDP (it runs with CURVE, or UDP is off)");
            d.probeTo = {isLocalHost(host) ? "127.0.0.1" : host, d.scene.endpoints.udpProbePort};
            d.probeSocket.emplace(udpLocal, 0);
        }
        d.connectSub();
    } catch (...) {
        d.sub.reset();  // not connected: connected() says so, and the sockets stop retrying
        d.dealer.reset();
        d.probeSocket.reset();
        d.udpFrames.reset();
        throw;
    }
    return d.scene;
}

const SceneInfo& ClientSession::scene() const {
    return impl_->scene;
}
bool ClientSession::connected() const {
    return impl_->sub.has_value();
}
int ClientSession::frameTier() const {
    return impl_->tier;
}
std::string ClientSession::frameEndpoint() const {
    return impl_->frameEndpoint;
}

bool ClientSession::sendProbe(const Probe& probe) {
    if (!impl_->dealer) throw std::logic_error("ClientSession::sendProbe before connect");
    const Buffer b = encodeProbe(probe);
    if (impl_->probeSocket) return impl_->probeSocket->sendTo(impl_->probeTo, b);
    if (!impl_->dealer->send(zmq::buffer(b), zmq::send_flags::dontwait)) return false;
    impl_->lastSent = Clock::now();
    return true;
}

void ClientSession::Impl::takeUdpFeedback() {
    // Datagrams may arrive out of order: the one of the latest step wins.
    while (auto d = probeSocket->receive(0)) {
        if (d->sender == probeTo && messageKind(d->bytes.data(), d->bytes.size()) == MessageKind::Refusal) {
            auto r = decodeRefusal(d->bytes.data(), d->bytes.size());
            if (r.ok())
                takeRefusal(std::move(r.value));
            else
                countMalformed();
            continue;
        }
        const auto f = decodeFeedback(d->bytes.data(), d->bytes.size());
        if (!f.ok() || !(d->sender == probeTo)) {
            countMalformed();
            continue;
        }
        if (!feedback || f.value.step >= feedback->step) feedback = f.value;
    }
}

CommandReply ClientSession::sendCommand(const Command& command) {
    return sendCommand(command, impl_->opt.receiveTimeout);
}

CommandReply ClientSession::sendCommand(const Command& command, milliseconds timeout) {
    Impl& d = *impl_;
    if (!d.dealer) throw std::logic_error("ClientSession::sendCommand before connect");
    d.send(encodeCommand(command), ("command " + std::to_string(command.requestId)).c_str());
    d.refusal.reset();
    std::optional<CommandReply> answer;
    d.pumpControl(Clock::now() + timeout, [&](const zmq::message_t& msg) {
        CommandReply r;
        const MessageKind k = d.takeControl(msg, &r);
        if (k == MessageKind::Refusal && d.refusal->kind == "Command") return true;  // its request id was unreadable
        if (k != MessageKind::CommandReply) return false;
        if (r.requestId == command.requestId) {
            answer = std::move(r);
            return true;
        }
        std::lock_guard lock(d.m);
        ++d.stats.repliesDropped;  // the late answer to an earlier request that timed out
        return false;
    });
    if (!answer && d.refusal && d.refusal->kind == "Command")
        throw Error(d.controlEndpoint,
                    "the server refused command " + std::to_string(command.requestId) + ": " + d.refusal->reason);
    if (!answer)
        throw Error(d.controlEndpoint,
                    "no reply to command " + std::to_string(command.requestId) + " within " + inMs(timeout));
    return std::move(*answer);
}

bool ClientSession::postCommand(const Command& command) {
    Impl& d = *impl_;
    if (!d.dealer) throw std::logic_error("ClientSession::postCommand before connect");
    const Buffer b = encodeCommand(command);
    if (!d.dealer->send(zmq::buffer(b), zmq::send_flags::dontwait)) return false;
    d.lastSent = Clock::now();
    return true;
}

std::optional<Feedback> ClientSession::pollFeedback() {
    Impl& d = *impl_;
    if (!d.dealer) return std::nullopt;
    d.pumpControl(Clock::now(), [&](const zmq::message_t& msg) {
        d.takeControl(msg, nullptr);
        return false;  // read everything queued: the newest feedback wins
    });
    if (d.probeSocket) d.takeUdpFeedback();
    d.keepAlive();
    return std::exchange(d.feedback, std::nullopt);
}

std::optional<Feedback> ClientSession::waitFeedback(Clock::time_point deadline) {
    Impl& d = *impl_;
    if (!d.dealer) throw std::logic_error("ClientSession::waitFeedback before connect");
    for (;;) {
        if (auto fb = pollFeedback()) return fb;
        const auto left = deadline - Clock::now();
        if (left <= Clock::duration::zero()) return std::nullopt;
        // ZeroMQ's descriptor only says that the socket's state may have changed; ZMQ_EVENTS,
        // read after every drain, says whether a message waits (and re-arms the descriptor).
        if (d.dealer->get(zmq::sockopt::events) & ZMQ_POLLIN) continue;
        pollfd fds[2] = {{d.dealer->get(zmq::sockopt::fd), POLLIN, 0},
                         {d.probeSocket ? d.probeSocket->fd() : -1, POLLIN, 0}};  // -1: ignored
        const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
        const timespec wait{time_t(ns / 1000000000), long(ns % 1000000000)};
        ppoll(fds, 2, &wait, nullptr);  // an interrupted wait just goes round again
    }
}

ClientStats ClientSession::stats() const {
    std::lock_guard lock(impl_->m);
    return impl_->stats;
}

void useCurveKeys(ClientOptions& o, const std::string& serverKeyFile, const std::string& clientPrefix) {
    if (!clientPrefix.empty() && serverKeyFile.empty())
        throw Error("--client-key", "needs --server-key: a client key pair is used in CURVE sessions only");
    if (serverKeyFile.empty()) return;
    o.curveServerKey = readCurveKey(serverKeyFile);
    if (clientPrefix.empty()) return;
    o.curvePublicKey = readCurveKey(clientPrefix + ".pub");
    o.curveSecretKey = readCurveKey(clientPrefix + ".key");
}

}  // namespace bop::protocol
