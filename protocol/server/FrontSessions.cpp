// The front's inbound side: every message from a peer checked (decoder, then the scene's ranges,
// server/InboundRanges.hpp), refused with a reason or taken, and the sessions that say Hello,
// kept while they talk and forgotten after FrontOptions::sessionTimeout of silence. Runs on the
// control thread (and in inject()) with the front's mutex held; answers go to the outbox.
#include "server/InboundRanges.hpp"
#include "server/ServerFrontImpl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bop::protocol {
namespace {

using Clock = front::Clock;

// Frames a client that wants `wantedHz` gets of a server publishing at `rateHz`: every 2^tier-th
// (docs/protocol.md, "Frame rate tiers").
int tierFor(float rateHz, float wantedHz) {
    if (!(wantedHz > 0) || wantedHz >= rateHz) return 0;
    // In double: a tiny wanted rate (1e-40 Hz) overflows a float ratio (a fuzz finding).
    return int(std::clamp(std::floor(std::log2(double(rateHz) / double(wantedHz))), 0.0, 7.0));
}

}  // namespace

void ServerFront::Impl::internalError(const std::string& what) {
    const std::uint64_t n = ++stats.internalErrors;
    stats.lastInternalError = what;
    if (n <= 3 || n % 1000 == 0)
        std::fprintf(stderr, "bop-server: network front: %s (internal error %llu; the front goes on)\n", what.c_str(),
                     (unsigned long long)n);
}

void ServerFront::Impl::handle(const std::string& id, const std::uint8_t* data, std::size_t size,
                               const std::function<std::string()>& peerAddress) {
    try {
        dispatch(id, data, size, peerAddress);
    } catch (const std::exception& e) {
        internalError(std::string("handling a message: ") + e.what());
    }
}

void ServerFront::Impl::count(DecodeError error) {
    if (error == DecodeError::None) return;  // a refusal by policy (hello first, read-only, ...)
    if (valueRefused(error))
        ++stats.outOfRange;
    else
        ++stats.malformed;
    if (error == DecodeError::TooLarge) ++stats.oversized;
}

void ServerFront::Impl::refuse(const std::string& id, MessageKind kind, std::uint64_t seq, DecodeError error,
                               const std::string& why) {
    count(error);
    const Clock::time_point now = Clock::now();
    const auto it = clients.find(id);
    std::uint64_t refused = stats.malformed + stats.outOfRange;  // without a session: the front's
    if (it != clients.end()) {
        refused = ++it->second.refused;
        if (!it->second.refusals.take(now, front::kRefusalsPerSecond)) return;
    } else if (!anonymousRefusals.take(now, front::kAnonymousRefusalsPerSecond)) {
        return;
    }
    Refusal r{kind == MessageKind::Unknown ? "unknown" : toString(kind), seq, why.substr(0, kMaxTextBytes), refused};
    outbox.emplace_back(id, encodeRefusal(r));
    ++stats.refusalsSent;
}

void ServerFront::Impl::refuse(const std::string& id, const Command& c, ReplyStatus status, DecodeError error,
                               const std::string& why) {
    count(error);
    if (const auto it = clients.find(id); it != clients.end()) ++it->second.refused;
    CommandReply r;
    r.requestId = c.requestId;
    r.status = status;
    r.message = why.substr(0, kMaxTextBytes);
    outbox.emplace_back(id, encodeCommandReply(r));
    ++stats.refusalsSent;
}

void ServerFront::Impl::updateRate() {
    float rate = opt.publishHz;
    for (const auto& [_, other] : clients) rate = std::max(rate, std::min(other.wantedHz, opt.maxPublishHz));
    rateHz = rate;
}

void ServerFront::Impl::hello(const std::string& id, const Decoded<Hello>& h,
                              const std::function<std::string()>& peerAddress) {
    if (!h) return refuse(id, MessageKind::Hello, 0, h.error, h.message);
    auto it = clients.find(id);
    if (it == clients.end()) {
        if (clients.size() >= front::kMaxSessions)
            return refuse(id, MessageKind::Hello, 0, DecodeError::None,
                          "Hello: server full (" + std::to_string(front::kMaxSessions) + " sessions)");
        it = clients.emplace(id, front::Client{}).first;
        ++stats.sessionsOpened;
    }
    ++stats.hellos;
    front::Client& c = it->second;
    c.lastHeard = Clock::now();  // a new session's
    c.wantedHz = h.value.frameRateHz;
    c.mayCommand = !h.value.readOnly && (opt.viewersMayCommand || h.value.role != Role::Viewer);
    updateRate();
    stats.clients = clients.size();
    if (udp) {  // a keep-alive Hello leaves the client's datagram sender as it is
        const std::uint16_t port = h.value.udpFramePort;
        const std::string address = port ? peerAddress() : std::string();
        const int tier = tierFor(rateHz, c.wantedHz);
        if (address != c.udpAddress || port != c.udpPort) {
            if (!udp->setFrameClient(id, address, port, tier))
                return refuse(id, MessageKind::Hello, 0, DecodeError::None,
                              "Hello.udp_frame_port: the server sends frames as datagrams to " +
                                  std::to_string(FrontUdp::kMaxFrameClients) +
                                  " clients at most; connect without a UDP frame port");
        } else if (tier != c.udpTier) {
            udp->setFrameTier(id, tier);
        }
        c.udpAddress = address;
        c.udpPort = port;
        c.udpTier = tier;
    }
    outbox.emplace_back(id, encodeSceneInfo(sceneNow()));
    helloSeen.notify_all();
}

void ServerFront::Impl::command(const std::string& id, const Decoded<Command>& c) {
    using E = DecodeError;
    if (!c) {  // a request id that could be read gets its reply; the rest a Refusal
        if (!c.read) return refuse(id, MessageKind::Command, 0, c.error, c.message);
        return refuse(id, c.value, c.error == E::Unsupported ? ReplyStatus::Unsupported : ReplyStatus::Rejected,
                      c.error, c.message);
    }
    ++stats.commands;
    const auto it = clients.find(id);
    if (it == clients.end()) return refuse(id, c.value, ReplyStatus::Rejected, E::None, "hello first");
    if (!it->second.mayCommand) return refuse(id, c.value, ReplyStatus::ReadOnly, E::None, "this session is read-only");
    if (const auto why = refuseCommand(c.value, scene))
        return refuse(id, c.value, ReplyStatus::Rejected, E::OutOfRange, *why);
    {
        std::lock_guard slots(inbound.m);
        if (inbound.commands.size() < front::kMaxQueuedCommands) {
            inbound.commands.push_back({id, c.value});
            return;
        }
    }
    refuse(id, c.value, ReplyStatus::Rejected, E::None, "server busy");
}

void ServerFront::Impl::dispatch(const std::string& id, const std::uint8_t* data, std::size_t size,
                                 const std::function<std::string()>& peerAddress) {
    // Any message keeps its sender's session, refused ones too: the client is there.
    if (const auto it = clients.find(id); it != clients.end()) it->second.lastHeard = Clock::now();
    const MessageKind kind = messageKind(data, size);
    switch (kind) {
        case MessageKind::Hello:
            return hello(id, decodeHello(data, size), peerAddress);
        case MessageKind::Command:
            return command(id, decodeCommand(data, size));
        case MessageKind::MapRequest: {
            const auto r = decodeMapRequest(data, size);
            if (!r) return refuse(id, kind, 0, r.error, r.message);
            const auto it = clients.find(id);
            if (it == clients.end()) return refuse(id, kind, 0, DecodeError::None, "MapRequest: hello first");
            if (const auto why = refuseMapRequest(r.value, scene))
                return refuse(id, kind, 0, DecodeError::OutOfRange, *why);
            outbox.emplace_back(id, mapPiece(r.value, it->second));
            return;
        }
        case MessageKind::MapEditsRequest: {
            const auto r = decodeMapEditsRequest(data, size);
            if (!r) return refuse(id, kind, 0, r.error, r.message);
            const auto it = clients.find(id);
            if (it == clients.end()) return refuse(id, kind, 0, DecodeError::None, "MapEditsRequest: hello first");
            outbox.emplace_back(id, mapEdits(r.value, it->second));
            return;
        }
        case MessageKind::Probe: {
            const auto p = decodeProbe(data, size);
            if (!p) return refuse(id, kind, p.read ? p.value.seq : 0, p.error, p.message);
            const auto it = clients.find(id);
            if (it == clients.end()) return refuse(id, kind, p.value.seq, DecodeError::None, "Probe: hello first");
            if (const auto why = refuseProbe(p.value, scene))
                return refuse(id, kind, p.value.seq, DecodeError::OutOfRange, *why);
            ++stats.probes;
            it->second.lastProbe = it->second.lastHeard;
            std::lock_guard slots(inbound.m);
            if (!inbound.probe || p.value.seq > inbound.probe->seq) inbound.probe = p.value;
            return;
        }
        default:
            return refuse(id, kind, 0, DecodeError::WrongIdentifier,
                          std::string(toString(kind)) + ": not a message a client sends to the server");
    }
}

void ServerFront::Impl::expire(Clock::time_point now) {
    if (opt.sessionTimeout.count() <= 0) return;
    bool any = false;
    for (auto it = clients.begin(); it != clients.end();) {
        if (now - it->second.lastHeard <= opt.sessionTimeout) {
            ++it;
            continue;
        }
        if (udp && it->second.udpPort) udp->setFrameClient(it->first, "", 0, 0);
        it = clients.erase(it);
        ++stats.sessionsExpired;
        any = true;
    }
    if (!any) return;
    stats.clients = clients.size();
    updateRate();
}

}  // namespace bop::protocol
