#pragma once
// ZeroMQ's authentication hook (ZAP, rfc.zeromq.org/spec/27) for the front's CURVE sockets: with
// a list of client public keys, a peer whose key is not on it is refused during the handshake,
// before any of its messages reach the server. Without a list (or without CURVE) no handler is
// bound and CURVE only encrypts and authenticates the server to its clients.
#include <zmq.hpp>

#include <array>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace bop::protocol {

class ZapHandler {
public:
    // Binds inproc://zeromq.zap.01 in `ctx`: do it before the CURVE sockets bind. `allowed`
    // holds z85 public keys (CurveKeys.hpp); bop::Error on a key that is not one.
    ZapHandler(zmq::context_t& ctx, const std::vector<std::string>& allowed);

    zmq::socket_t& socket() { return rep_; }
    // Answers every request queued now, without waiting. Returns how many peers it refused.
    std::uint64_t serve();

private:
    zmq::socket_t rep_;
    std::set<std::array<std::uint8_t, 32>> allowed_;
};

}  // namespace bop::protocol
