#include "security/ZapHandler.hpp"

#include "bop/common/Error.hpp"
#include "security/CurveKeys.hpp"

#include <cstring>

namespace bop::protocol {
namespace {

constexpr const char* kZapEndpoint = "inproc://zeromq.zap.01";  // fixed by the ZAP specification
constexpr std::size_t kKeyBytes = 32;

}  // namespace

ZapHandler::ZapHandler(zmq::context_t& ctx, const std::vector<std::string>& allowed)
    : rep_(ctx, zmq::socket_type::rep) {
    for (const std::string& z85 : allowed) {
        if (!isCurveKey(z85))
            throw Error("CURVE client key", "\"" + z85 + "\" is not a z85 public key (40 characters)");
        std::array<std::uint8_t, kKeyBytes> key{};
        zmq_z85_decode(key.data(), z85.c_str());
        allowed_.insert(key);
    }
    rep_.set(zmq::sockopt::linger, 0);
    rep_.bind(kZapEndpoint);
}

std::uint64_t ZapHandler::serve() {
    std::uint64_t refused = 0;
    for (;;) {
        // Request: version, request id, domain, address, identity, mechanism, credentials...
        std::vector<zmq::message_t> parts;
        zmq::message_t part;
        if (!rep_.recv(part, zmq::recv_flags::dontwait)) return refused;
        parts.push_back(std::move(part));
        while (parts.back().more() && parts.size() < 16) {
            zmq::message_t next;
            if (!rep_.recv(next, zmq::recv_flags::dontwait)) break;  // parts arrive together
            parts.push_back(std::move(next));
        }
        const bool wellFormed = parts.size() >= 7 && parts[0].to_string_view() == "1.0";
        const bool curve = wellFormed && parts[5].to_string_view() == "CURVE" && parts[6].size() == kKeyBytes;
        bool ok = false;
        if (curve) {
            std::array<std::uint8_t, kKeyBytes> key{};
            std::memcpy(key.data(), parts[6].data(), kKeyBytes);
            ok = allowed_.count(key) > 0;
        }
        refused += !ok;
        const std::string id = parts.size() >= 2 ? parts[1].to_string() : std::string();
        const char* status = !wellFormed ? "500" : ok ? "200" : "400";
        const char* text = !wellFormed ? "malformed ZAP request" : ok ? "OK" : "client key not allowed";
        rep_.send(zmq::str_buffer("1.0"), zmq::send_flags::sndmore);
        rep_.send(zmq::buffer(id), zmq::send_flags::sndmore);
        rep_.send(zmq::buffer(std::string_view(status)), zmq::send_flags::sndmore);
        rep_.send(zmq::buffer(std::string_view(text)), zmq::send_flags::sndmore);
        rep_.send(zmq::str_buffer(""), zmq::send_flags::sndmore);  // user id
        rep_.send(zmq::str_buffer(""), zmq::send_flags::none);     // metadata
    }
}

}  // namespace bop::protocol
