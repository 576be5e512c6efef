#include "server/FrontUdp.hpp"

#include "codec/MessageKind.hpp"
#include "server/InboundRanges.hpp"

#include <cstdio>

namespace bop::protocol {
namespace {

std::string parts(const Endpoint& e) {
    return e.address + ":" + std::to_string(e.port);
}

Endpoint endpointOf(const std::string& text) {
    const auto colon = text.rfind(':');
    return {text.substr(0, colon), std::uint16_t(std::stoi(text.substr(colon + 1)))};
}

}  // namespace

FrontUdp::FrontUdp(const std::string& bindAddress, int port)
    : socket_(bindAddress == "*" ? "0.0.0.0" : bindAddress, std::uint16_t(port)) {}

void FrontUdp::refuse(const Endpoint& sender, const Probe* p, DecodeError e, const std::string& why,
                      Clock::time_point now, Inbound& in, std::size_t datagramBytes) {
    if (valueRefused(e))
        ++in.outOfRange;
    else
        ++in.malformed;
    if (e == DecodeError::TooLarge) ++in.oversized;
    if (!p) return;  // unreadable: perhaps not even from the address it names
    Refused& r = refused_[sender.address];
    ++r.count;
    if (now - r.lastSent < std::chrono::seconds(1)) return;
    if (now - refusalSecond_ > std::chrono::seconds(1)) refusalSecond_ = now, refusalsThisSecond_ = 0;
    if (++refusalsThisSecond_ > kRefusalsPerSecond) return;
    r.lastSent = now;
    Refusal answer{"Probe", p->seq, why.substr(0, kMaxTextBytes), r.count};
    Buffer b = encodeRefusal(answer);
    if (b.size() > datagramBytes) {  // never more bytes back than came: no amplification
        const std::size_t cut = std::min(answer.reason.size(), b.size() - datagramBytes);
        answer.reason.resize(answer.reason.size() - cut);
        b = encodeRefusal(answer);
        if (b.size() > datagramBytes) return;
    }
    try {
        socket_.sendTo(sender, b);
        ++in.refusalsSent;
    } catch (const std::exception&) {  // a refusal that cannot go is a lost datagram
    }
}

FrontUdp::Inbound FrontUdp::poll(Clock::time_point now, const SceneInfo& scene) {
    Inbound in;
    for (int k = 0; k < 256; ++k) {  // a burst; the rest next time round
        auto d = socket_.receive(0);
        if (!d) break;
        const auto p = decodeProbe(d->bytes.data(), d->bytes.size());
        if (!p) {
            refuse(d->sender, p.read ? &p.value : nullptr, p.error, p.message, now, in, d->bytes.size());
            continue;
        }
        if (const auto why = refuseProbe(p.value, scene)) {
            refuse(d->sender, &p.value, DecodeError::OutOfRange, *why, now, in, d->bytes.size());
            continue;
        }
        ++in.probes;
        probers_[parts(d->sender)] = now;
        if (!in.newest || p.value.seq > in.newest->seq) in.newest = p.value;
    }
    for (auto it = refused_.begin(); it != refused_.end();)  // the table holds the last second's senders only
        it = now - it->second.lastSent > std::chrono::seconds(1) ? refused_.erase(it) : std::next(it);
    return in;
}

void FrontUdp::feedback(const Buffer& b, Clock::time_point now) {
    for (auto it = probers_.begin(); it != probers_.end();) {
        if (now - it->second > std::chrono::seconds(1)) {
            it = probers_.erase(it);
            continue;
        }
        try {
            socket_.sendTo(endpointOf(it->first), b);  // a drop is a lost datagram, as UDP allows
            ++it;
        } catch (const std::exception& e) {  // that client's trouble, not the server's: forget it
            // It comes back with its next probe: the first few and then every 1000th are said.
            if (++sendFailures_ <= 3 || sendFailures_ % 1000 == 0)
                std::fprintf(stderr, "bop-server: feedback datagrams to %s stopped (%llu failures so far): %s\n",
                             it->first.c_str(), (unsigned long long)sendFailures_, e.what());
            it = probers_.erase(it);
        }
    }
}

bool FrontUdp::anyProbing(Clock::time_point now) const {
    for (const auto& [_, t] : probers_)
        if (now - t <= std::chrono::seconds(1)) return true;
    return false;
}

bool FrontUdp::setFrameClient(const std::string& id, const std::string& address, std::uint16_t port, int tier) {
    std::lock_guard lock(frameMutex_);
    if (port == 0) {
        frameClients_.erase(id);
        return true;
    }
    if (!frameClients_.count(id) && frameClients_.size() >= kMaxFrameClients) return false;
    FrameClient c;
    c.sender = std::make_unique<UdpSender>(UdpSocket(socket_.local().address, 0), Endpoint{address, port});
    c.tier = tier;
    frameClients_[id] = std::move(c);
    return true;
}

void FrontUdp::setFrameTier(const std::string& id, int tier) {
    std::lock_guard lock(frameMutex_);
    if (const auto it = frameClients_.find(id); it != frameClients_.end()) it->second.tier = tier;
}

void FrontUdp::frame(const Buffer& whole, std::uint64_t frameNumber) {
    std::lock_guard lock(frameMutex_);
    for (auto it = frameClients_.begin(); it != frameClients_.end();) {
        try {
            // Numbered by the frame: a client's new sender (a new address) goes on upwards, and
            // its receiver never takes the next frames for stale ones.
            if (frameNumber % (std::uint64_t(1) << it->second.tier) == 0)
                it->second.sender->send(kFrameStream, std::uint32_t(frameNumber), whole);
            ++it;
        } catch (const std::exception& e) {  // that client's trouble, not the server's: it gets no more
            std::fprintf(stderr, "bop-server: frame datagrams to %s stopped: %s\n",
                         it->second.sender->destination().text().c_str(), e.what());
            it = frameClients_.erase(it);
        }
    }
}

bool FrontUdp::wantsFrame(std::uint64_t frameNumber) const {
    std::lock_guard lock(frameMutex_);
    for (const auto& [_, c] : frameClients_)
        if (frameNumber % (std::uint64_t(1) << c.tier) == 0) return true;
    return false;
}

std::uint64_t FrontUdp::datagramsDropped() const {
    std::lock_guard lock(frameMutex_);
    std::uint64_t n = 0;
    for (const auto& [_, c] : frameClients_) n += c.sender->stats().datagramsDropped;
    return n;
}

}  // namespace bop::protocol
