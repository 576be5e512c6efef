#pragma once
// bop-igtl's OpenIGTLink side: a TCP server for any number of clients (3D Slicer's OpenIGTLinkIF,
// PLUS, a tracker), on a thread of its own, bound to 127.0.0.1 unless told otherwise. Outgoing,
// each client has a slot per device name holding the newest message for it, and a greeting sent
// once when it connects: sends never block, so a client that reads slowly gets fewer updates and
// one that never reads holds one message per device and costs the others nothing. Incoming,
// every header and body goes through IgtlWire.hpp: a header that breaks a rule closes that
// connection (the stream cannot be followed past it), a body with a wrong CRC or of a type
// bop-igtl does not read is skipped; each is logged with the reason.
#include "IgtlMessages.hpp"
#include "IgtlWire.hpp"

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace bop::igtl {

struct ServerOptions {
    std::string bind = "127.0.0.1";  // an IPv4 address of this host, or "*" for every interface
    int port = 18944;                // OpenIGTLink's usual port; 0: one the system picks
};

struct ServerStats {
    std::size_t clients = 0;     // connected now
    std::size_t accepted = 0;    // connections since the start
    std::size_t received = 0;    // messages handed on
    std::size_t skipped = 0;     // whole messages not read (wrong CRC, types bop-igtl does not read)
    std::size_t closed = 0;      // connections closed for a header that broke the rules
    std::uint64_t sent = 0;      // messages sent whole, all clients
    std::uint64_t replaced = 0;  // messages replaced by a newer one of their device before being sent
    std::string lastRefusal;     // why the last message or connection was refused
};

class Server {
public:
    // A message read whole with a valid CRC, of a type in `reads` (on the server's thread).
    using OnMessage = std::function<void(const Header&, std::span<const std::uint8_t> content)>;
    using Log = std::function<void(const std::string&)>;

    // Listens at once (std::runtime_error naming the address when it cannot).
    Server(ServerOptions options, std::vector<std::string> reads, OnMessage onMessage, Log log);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    int port() const { return port_; }
    // The newest message of `device` for every client connected (replacing one not yet sent).
    void publish(const std::string& device, Bytes message);
    // Sent to each client once, before anything else, when it connects; and now to those connected.
    void setGreeting(std::vector<Bytes> messages);
    ServerStats stats() const;

private:
    struct Client;
    void run();
    void accept();
    bool write(Client& c);  // false: the connection is gone
    bool read(Client& c);   // false: close it
    void refuse(Client& c, const std::string& why, bool close);

    const std::vector<std::string> reads_;
    const OnMessage onMessage_;
    const Log log_;
    int listen_ = -1, wake_ = -1, port_ = 0;
    mutable std::mutex m_;
    std::vector<std::unique_ptr<Client>> clients_;
    std::vector<std::shared_ptr<const Bytes>> greeting_;
    ServerStats stats_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace bop::igtl
