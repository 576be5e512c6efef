#include "IgtlServer.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <deque>
#include <stdexcept>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

namespace bop::igtl {

struct Server::Client {
    int fd = -1;
    std::string peer;
    std::deque<std::shared_ptr<const Bytes>> greeting;           // still to send, in order
    std::map<std::string, std::shared_ptr<const Bytes>> newest;  // per device, not yet sent
    std::shared_ptr<const Bytes> sending;                        // under way, from `offset`
    std::size_t offset = 0;
    std::vector<std::uint8_t> in;  // received, not yet taken: a header, or a header and its body
    Header header;
    bool haveHeader = false;
    std::vector<std::string> skippedTypes;  // logged once each
    bool wantsOutput() const { return sending || !greeting.empty() || !newest.empty(); }
};

namespace {

constexpr int kSendBufferBytes = 1 << 20;

void nonBlocking(int fd) {
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK);
}

std::string errnoText(const std::string& what) {
    return what + ": " + std::strerror(errno);
}

}  // namespace

Server::Server(ServerOptions options, std::vector<std::string> reads, OnMessage onMessage, Log log)
    : reads_(std::move(reads)), onMessage_(std::move(onMessage)), log_(std::move(log)) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(options.port));
    if (options.bind == "*")
        a.sin_addr.s_addr = htonl(INADDR_ANY);
    else if (inet_pton(AF_INET, options.bind.c_str(), &a.sin_addr) != 1)
        throw std::runtime_error("OpenIGTLink bind address '" + options.bind +
                                 "' is not an IPv4 address (or '*' for every interface)");
    if (options.port < 0 || options.port > 65535)
        throw std::runtime_error("OpenIGTLink port " + std::to_string(options.port) + " is not in 0..65535");
    listen_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    setsockopt(listen_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (listen_ < 0 || bind(listen_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::listen(listen_, 16) != 0) {
        const std::string why =
            errnoText("cannot listen for OpenIGTLink on " + options.bind + ":" + std::to_string(options.port));
        if (listen_ >= 0) close(listen_);
        throw std::runtime_error(why);
    }
    socklen_t len = sizeof a;
    getsockname(listen_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    nonBlocking(listen_);
    wake_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    thread_ = std::thread([this] { run(); });
}

Server::~Server() {
    stop_ = true;
    const std::uint64_t one = 1;
    if (::write(wake_, &one, sizeof one) < 0) {
    }  // the loop also wakes every 100 ms
    thread_.join();
    for (auto& c : clients_) close(c->fd);
    close(listen_);
    close(wake_);
}

void Server::publish(const std::string& device, Bytes message) {
    auto shared = std::make_shared<const Bytes>(std::move(message));
    {
        std::lock_guard lock(m_);
        for (auto& c : clients_) {
            auto& slot = c->newest[device];
            if (slot) ++stats_.replaced;
            slot = shared;
        }
    }
    const std::uint64_t one = 1;
    if (::write(wake_, &one, sizeof one) < 0) {
    }  // already signalled: the counter is full only after 2^64 - 2 writes
}

void Server::setGreeting(std::vector<Bytes> messages) {
    std::lock_guard lock(m_);
    greeting_.clear();
    for (auto& b : messages) greeting_.push_back(std::make_shared<const Bytes>(std::move(b)));
    for (auto& c : clients_) c->greeting.insert(c->greeting.end(), greeting_.begin(), greeting_.end());
}

ServerStats Server::stats() const {
    std::lock_guard lock(m_);
    ServerStats s = stats_;
    s.clients = clients_.size();
    return s;
}

void Server::run() {
    std::vector<pollfd> fds;
    while (!stop_) {
        {
            std::lock_guard lock(m_);
            fds.assign({{wake_, POLLIN, 0}, {listen_, POLLIN, 0}});
            for (auto& c : clients_) fds.push_back({c->fd, short(POLLIN | (c->wantsOutput() ? POLLOUT : 0)), 0});
        }
        if (poll(fds.data(), fds.size(), 100) < 0 && errno != EINTR) {
            log_(errnoText("OpenIGTLink server: poll"));
            return;
        }
        std::lock_guard lock(m_);
        if (fds[0].revents & POLLIN) {
            std::uint64_t n;
            if (::read(wake_, &n, sizeof n) < 0) {
            }  // drained
        }
        if (fds[1].revents & POLLIN) accept();
        // Clients that were polled: those present before accept() (new ones come last).
        for (std::size_t k = 2; k < fds.size(); ++k) {
            Client& c = *clients_[k - 2];
            bool keep = true;
            if (fds[k].revents & (POLLERR | POLLHUP | POLLNVAL))
                keep = (fds[k].revents & POLLIN) && read(c);
            else if (fds[k].revents & POLLIN)
                keep = read(c);
            if (keep) keep = write(c);  // whatever is waiting, as far as the socket takes it
            if (!keep) {
                close(c.fd);
                c.fd = -1;
            }
        }
        const auto gone = std::remove_if(clients_.begin(), clients_.end(), [&](const auto& c) {
            if (c->fd >= 0) return false;
            log_("OpenIGTLink client " + c->peer + " disconnected");
            return true;
        });
        clients_.erase(gone, clients_.end());
    }
}

void Server::accept() {
    for (;;) {
        sockaddr_in a{};
        socklen_t len = sizeof a;
        const int fd = accept4(listen_, reinterpret_cast<sockaddr*>(&a), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (fd < 0) return;
        const int one = 1;
        setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        // A small kernel buffer: a client that stops reading holds little, and one that reads
        // slowly gets the newest messages rather than a backlog (the kernel grows its own to 4 MB).
        const int sendBuffer = kSendBufferBytes;
        setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &sendBuffer, sizeof sendBuffer);
        auto c = std::make_unique<Client>();
        c->fd = fd;
        char host[INET_ADDRSTRLEN] = "?";
        inet_ntop(AF_INET, &a.sin_addr, host, sizeof host);
        c->peer = std::string(host) + ":" + std::to_string(ntohs(a.sin_port));
        c->greeting.assign(greeting_.begin(), greeting_.end());
        ++stats_.accepted;
        log_("OpenIGTLink client " + c->peer + " connected");
        write(*c);
        clients_.push_back(std::move(c));
    }
}

bool Server::write(Client& c) {
    for (;;) {
        if (!c.sending) {
            if (!c.greeting.empty()) {
                c.sending = c.greeting.front();
                c.greeting.pop_front();
            } else if (!c.newest.empty()) {
                c.sending = c.newest.begin()->second;
                c.newest.erase(c.newest.begin());
            } else {
                return true;
            }
            c.offset = 0;
        }
        const Bytes& b = *c.sending;
        const ssize_t n = send(c.fd, b.data() + c.offset, b.size() - c.offset, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
        c.offset += std::size_t(n);
        if (c.offset < b.size()) return true;  // the socket is full: the rest when it drains
        c.sending.reset();
        ++stats_.sent;
    }
}

void Server::refuse(Client& c, const std::string& why, bool closing) {
    stats_.lastRefusal = why;
    log_("OpenIGTLink client " + c.peer + ": " + why + (closing ? "; connection closed" : "; message skipped"));
}

bool Server::read(Client& c) {
    std::uint8_t buffer[1 << 16];
    for (;;) {
        const ssize_t n = recv(c.fd, buffer, sizeof buffer, MSG_DONTWAIT);
        if (n == 0) return false;  // closed by the client
        if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
        c.in.insert(c.in.end(), buffer, buffer + n);
        for (;;) {  // every whole header, and body, received
            if (!c.haveHeader) {
                if (c.in.size() < kHeaderSize) break;
                std::string error;
                if (!readHeader(std::span<const std::uint8_t, kHeaderSize>(c.in.data(), kHeaderSize), c.header,
                                error)) {
                    ++stats_.closed;
                    refuse(c, error, true);
                    return false;
                }
                c.haveHeader = true;
            }
            const std::size_t whole = kHeaderSize + std::size_t(c.header.bodySize);
            if (c.in.size() < whole) break;
            const std::span<const std::uint8_t> body(c.in.data() + kHeaderSize, std::size_t(c.header.bodySize));
            std::span<const std::uint8_t> content;
            std::string error;
            const bool wanted = std::find(reads_.begin(), reads_.end(), c.header.type) != reads_.end();
            if (!wanted) {
                ++stats_.skipped;
                if (std::find(c.skippedTypes.begin(), c.skippedTypes.end(), c.header.type) == c.skippedTypes.end()) {
                    c.skippedTypes.push_back(c.header.type);
                    refuse(c, c.header.type + " is not a type bop-igtl reads", false);
                }
            } else if (!readContent(c.header, body, content, error)) {
                ++stats_.skipped;
                refuse(c, error, false);
            } else {
                ++stats_.received;
                onMessage_(c.header, content);
            }
            c.in.erase(c.in.begin(), c.in.begin() + std::ptrdiff_t(whole));
            c.haveHeader = false;
        }
    }
}

}  // namespace bop::igtl
