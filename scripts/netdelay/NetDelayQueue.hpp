#pragma once
// A netfilter queue whose packets are let through late: each packet the kernel queues (an
// iptables rule `-j NFQUEUE --queue-num N`) is held for a delay, plus a normally distributed jitter, cut at
// zero, and then accepted. Only the packet's metadata crosses to this process; the kernel keeps
// the packet. Packets may overtake each other with jitter, as with netem.
#include <chrono>
#include <cstdint>
#include <queue>
#include <random>
#include <vector>

struct nfq_handle;
struct nfq_q_handle;

namespace bop::netdelay {

using Clock = std::chrono::steady_clock;

struct DelayStats {
    std::uint64_t delayed = 0;    // packets held and accepted
    std::uint64_t overflows = 0;  // times the kernel dropped queue notifications (ENOBUFS)
    double largestLateMs = 0;     // the latest a packet left after its time, ms
};

class DelayQueue {
public:
    // bop::Error naming the queue when it cannot be bound (not root, another process holds it).
    DelayQueue(std::uint16_t queue, double delayMs, double jitterMs, std::uint32_t seed);
    ~DelayQueue();  // accepts whatever it still holds, then unbinds
    DelayQueue(const DelayQueue&) = delete;
    DelayQueue& operator=(const DelayQueue&) = delete;

    int fd() const { return fd_; }
    void receive();                       // takes what the kernel has queued, without waiting
    void release(Clock::time_point now);  // accepts every packet whose time has come
    // When the next held packet is due (Clock::time_point::max() when none is held).
    Clock::time_point nextDue() const;
    const DelayStats& stats() const { return stats_; }

    void hold(std::uint32_t packetId, Clock::time_point arrived);  // for the queue's callback

private:
    struct Held {
        Clock::time_point due;
        std::uint32_t id;
        bool operator>(const Held& o) const { return due > o.due; }
    };
    nfq_handle* handle_ = nullptr;
    nfq_q_handle* queue_ = nullptr;
    int fd_ = -1;
    double delayMs_, jitterMs_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> jitter_{0.0, 1.0};
    std::priority_queue<Held, std::vector<Held>, std::greater<>> held_;
    std::vector<char> buffer_;
    DelayStats stats_;
};

}  // namespace bop::netdelay
