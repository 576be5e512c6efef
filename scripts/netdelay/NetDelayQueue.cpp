#include "NetDelayQueue.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include <arpa/inet.h>
#include <libnetfilter_queue/libnetfilter_queue.h>
#include <linux/netfilter.h>  // NF_ACCEPT; after the libc headers, whose in_addr it then leaves alone
#include <sys/socket.h>

namespace bop::netdelay {
namespace {

int onPacket(nfq_q_handle*, nfgenmsg*, nfq_data* nfa, void* data) {
    const nfqnl_msg_packet_hdr* h = nfq_get_msg_packet_hdr(nfa);
    if (h) static_cast<DelayQueue*>(data)->hold(ntohl(h->packet_id), Clock::now());
    return 0;
}

}  // namespace

DelayQueue::DelayQueue(std::uint16_t queue, double delayMs, double jitterMs, std::uint32_t seed)
    : delayMs_(delayMs), jitterMs_(jitterMs), rng_(seed), buffer_(1 << 16) {
    const std::string where = "netfilter queue " + std::to_string(queue);
    handle_ = nfq_open();
    if (!handle_) throw Error(where, std::string("cannot open netlink (root is needed): ") + std::strerror(errno));
    queue_ = nfq_create_queue(handle_, queue, &onPacket, this);
    if (!queue_) {
        nfq_close(handle_);
        throw Error(where, "cannot bind it (another process holds it, or no permission)");
    }
    // Metadata only: the kernel keeps the packet until our verdict.
    // A full queue lets packets through undelayed rather than dropping them (fail open).
    if (nfq_set_mode(queue_, NFQNL_COPY_META, 0) < 0 || nfq_set_queue_maxlen(queue_, 65536) < 0 ||
        nfq_set_queue_flags(queue_, NFQA_CFG_F_FAIL_OPEN, NFQA_CFG_F_FAIL_OPEN) < 0) {
        nfq_destroy_queue(queue_);
        nfq_close(handle_);
        throw Error(where, "cannot configure it");
    }
    fd_ = nfq_fd(handle_);
    const int bytes = 8 << 20;
    setsockopt(fd_, SOL_SOCKET, SO_RCVBUFFORCE, &bytes, sizeof bytes);  // root: past rmem_max
}

DelayQueue::~DelayQueue() {
    release(Clock::time_point::max());
    nfq_destroy_queue(queue_);
    nfq_close(handle_);
}

void DelayQueue::hold(std::uint32_t packetId, Clock::time_point arrived) {
    const double ms = std::max(0.0, delayMs_ + jitterMs_ * jitter_(rng_));
    held_.push({arrived + std::chrono::nanoseconds(std::int64_t(ms * 1e6)), packetId});
}

void DelayQueue::receive() {
    for (;;) {
        const ssize_t n = recv(fd_, buffer_.data(), buffer_.size(), MSG_DONTWAIT);
        if (n > 0) {
            nfq_handle_packet(handle_, buffer_.data(), int(n));
            continue;
        }
        if (n < 0 && errno == ENOBUFS) {  // notifications lost: their packets stay queued until we exit
            ++stats_.overflows;
            continue;
        }
        return;  // EAGAIN: nothing more now
    }
}

void DelayQueue::release(Clock::time_point now) {
    while (!held_.empty() && held_.top().due <= now) {
        const Held h = held_.top();
        held_.pop();
        nfq_set_verdict(queue_, h.id, NF_ACCEPT, 0, nullptr);
        ++stats_.delayed;
        if (now != Clock::time_point::max())
            stats_.largestLateMs =
                std::max(stats_.largestLateMs, std::chrono::duration<double, std::milli>(now - h.due).count());
    }
}

Clock::time_point DelayQueue::nextDue() const {
    return held_.empty() ? Clock::time_point::max() : held_.top().due;
}

}  // namespace bop::netdelay
