#pragma once
// A bound IPv4 UDP socket (POSIX): send a datagram to an address, wait a bounded time for one.
// Addresses are numeric IPv4 ("127.0.0.1", "0.0.0.0" for all interfaces): no name lookup, so
// no call blocks on DNS. Errors throw bop::Error naming the address, port and the system's text.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bop::protocol {

struct Endpoint {
    std::string address;  // numeric IPv4
    std::uint16_t port = 0;
    bool operator==(const Endpoint&) const = default;
    std::string text() const;  // "127.0.0.1:5000"
};

struct Datagram {
    std::vector<std::uint8_t> bytes;
    Endpoint sender;
};

class UdpSocket {
public:
    // Kernel buffers asked for (bytes): a 3 MB frame arrives as ~2600 datagrams in a burst, and
    // the default 208 KiB receive buffer drops most of it. Linux grants at most
    // net.core.rmem_max / wmem_max; a smaller grant is not an error (see receiveBufferBytes()).
    static constexpr int kDefaultBufferBytes = 4 << 20;

    // Binds to address:port; port 0 picks a free ephemeral port (boundPort() tells which).
    explicit UdpSocket(const std::string& address = "127.0.0.1", std::uint16_t port = 0,
                       int bufferBytes = kDefaultBufferBytes);
    ~UdpSocket();
    UdpSocket(UdpSocket&& other) noexcept;
    UdpSocket& operator=(UdpSocket&& other) noexcept;
    UdpSocket(const UdpSocket&) = delete;
    UdpSocket& operator=(const UdpSocket&) = delete;

    std::uint16_t boundPort() const { return local_.port; }
    const Endpoint& local() const { return local_; }
    int fd() const { return fd_; }   // for poll(); -1 once moved from
    int receiveBufferBytes() const;  // as granted by the kernel (Linux reports twice the ask)
    int sendBufferBytes() const;

    // Sends one datagram. Returns false when the network dropped it at once (no buffer space,
    // host or network unreachable, refused): datagram mode tolerates loss, the caller counts it.
    // Throws on errors of use: bad address, datagram too large (EMSGSIZE), closed socket.
    bool sendTo(const Endpoint& to, std::span<const std::uint8_t> bytes);

    // The next datagram, waiting at most timeoutMs milliseconds (0: only what is queued now;
    // negative counts as 0). nullopt when none came in time. Retries when a signal interrupts.
    std::optional<Datagram> receive(int timeoutMs);

private:
    void close() noexcept;

    int fd_ = -1;
    Endpoint local_;
    std::vector<std::uint8_t> buffer_;  // 64 KiB from the first receive: any UDP datagram over IPv4 fits
};

}  // namespace bop::protocol
