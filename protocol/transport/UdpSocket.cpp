// POSIX UDP socket: blocking sends (a full send buffer empties in microseconds), receives that
// poll() with a deadline and never block beyond it.
#include "transport/UdpSocket.hpp"

#include "bop/common/Error.hpp"

#include <cerrno>
#include <chrono>
#include <system_error>
#include <utility>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace bop::protocol {

namespace {

constexpr std::size_t kReceiveBufferBytes = 65536;  // > 65507, the largest IPv4 UDP payload

std::string systemText(int err) {
    return std::generic_category().message(err);
}

sockaddr_in toSockaddr(const Endpoint& e) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(e.port);
    if (inet_pton(AF_INET, e.address.c_str(), &a.sin_addr) != 1)
        throw Error("UDP " + e.text(), "expected a numeric IPv4 address such as 127.0.0.1");
    return a;
}

Endpoint fromSockaddr(const sockaddr_in& a) {
    char text[INET_ADDRSTRLEN] = {};
    inet_ntop(AF_INET, &a.sin_addr, text, sizeof text);
    return {text, ntohs(a.sin_port)};
}

int socketIntOption(int fd, int option) {
    int value = 0;
    socklen_t len = sizeof value;
    if (getsockopt(fd, SOL_SOCKET, option, &value, &len) != 0) return -1;
    return value;
}

}  // namespace

std::string Endpoint::text() const {
    return address + ":" + std::to_string(port);
}

UdpSocket::UdpSocket(const std::string& address, std::uint16_t port, int bufferBytes) : local_{address, port} {
    const sockaddr_in a = toSockaddr(local_);
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) {
        const int err = errno;
        throw Error("UDP " + local_.text(), "cannot create a socket: " + systemText(err));
    }
    // Best effort: without privileges the kernel caps the size, and a failure only means more
    // loss under bursts, which datagram mode tolerates.
    if (bufferBytes > 0) {
        (void)setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &bufferBytes, sizeof bufferBytes);
        (void)setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &bufferBytes, sizeof bufferBytes);
    }
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
        const int err = errno;
        close();
        throw Error("UDP " + local_.text(), "cannot bind: " + systemText(err));
    }
    sockaddr_in bound{};
    socklen_t len = sizeof bound;
    if (getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &len) != 0) {
        const int err = errno;
        close();
        throw Error("UDP " + local_.text(), "cannot read the bound port: " + systemText(err));
    }
    local_.port = ntohs(bound.sin_port);
}

UdpSocket::~UdpSocket() {
    close();
}

UdpSocket::UdpSocket(UdpSocket&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), local_(std::move(other.local_)), buffer_(std::move(other.buffer_)) {}

UdpSocket& UdpSocket::operator=(UdpSocket&& other) noexcept {
    if (this != &other) {
        close();
        fd_ = std::exchange(other.fd_, -1);
        local_ = std::move(other.local_);
        buffer_ = std::move(other.buffer_);
    }
    return *this;
}

void UdpSocket::close() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

int UdpSocket::receiveBufferBytes() const {
    return socketIntOption(fd_, SO_RCVBUF);
}
int UdpSocket::sendBufferBytes() const {
    return socketIntOption(fd_, SO_SNDBUF);
}

bool UdpSocket::sendTo(const Endpoint& to, std::span<const std::uint8_t> bytes) {
    if (fd_ < 0) throw Error("UDP " + to.text(), "send on a closed (moved-from) socket");
    const sockaddr_in a = toSockaddr(to);
    for (;;) {
        const ssize_t n = ::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&a), sizeof a);
        if (n >= 0) return true;
        const int err = errno;
        switch (err) {
            case EINTR:
                continue;
            case EAGAIN:
#if EWOULDBLOCK != EAGAIN
            case EWOULDBLOCK:
#endif
            case ENOBUFS:
            case ECONNREFUSED:
            case EHOSTUNREACH:
            case ENETUNREACH:
            case EHOSTDOWN:
            case ENETDOWN:
            case EPERM:          // a packet filter on this host refused it: lost, as on the wire
            case EADDRNOTAVAIL:  // the local address went away with its interface
                return false;
            default:
                throw Error("UDP " + local_.text() + " -> " + to.text(),
                            "cannot send " + std::to_string(bytes.size()) + " bytes: " + systemText(err));
        }
    }
}

std::optional<Datagram> UdpSocket::receive(int timeoutMs) {
    using Clock = std::chrono::steady_clock;
    if (fd_ < 0) throw Error("UDP " + local_.text(), "receive on a closed (moved-from) socket");
    const auto deadline = Clock::now() + std::chrono::milliseconds(timeoutMs > 0 ? timeoutMs : 0);
    for (;;) {
        sockaddr_in from{};
        socklen_t len = sizeof from;
        // MSG_DONTWAIT: the socket stays blocking for sends; receives never block here.
        if (buffer_.empty()) buffer_.resize(kReceiveBufferBytes);  // a socket that only sends never needs it
        const ssize_t n =
            ::recvfrom(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT, reinterpret_cast<sockaddr*>(&from), &len);
        if (n >= 0) return Datagram{{buffer_.begin(), buffer_.begin() + n}, fromSockaddr(from)};
        const int err = errno;
        // ECONNREFUSED: an ICMP error for an earlier send; it concerns no datagram to read.
        if (err != EAGAIN && err != EWOULDBLOCK && err != EINTR && err != ECONNREFUSED)
            throw Error("UDP " + local_.text(), "cannot receive: " + systemText(err));
        if (err != EAGAIN && err != EWOULDBLOCK) continue;
        const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) return std::nullopt;
        pollfd p{fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
        if (ready < 0 && errno != EINTR) {
            const int perr = errno;
            throw Error("UDP " + local_.text(), "cannot wait for data: " + systemText(perr));
        }
        // ready == 0: time is up, checked at the top after one more non-blocking read.
    }
}

}  // namespace bop::protocol
