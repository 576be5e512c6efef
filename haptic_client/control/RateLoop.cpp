#include "control/RateLoop.hpp"

#include "control/ThreadTimes.hpp"

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <ctime>

namespace bop::haptic {
namespace {

constexpr std::int64_t kNsPerS = 1'000'000'000;
// Up to this many periods late, the next ticks run at once until the loop is on time again (the
// rate holds); later than that, the deadlines in between are skipped (no burst after a stall).
constexpr std::int64_t kCatchUpPeriods = 4;

std::int64_t nowNs() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return std::int64_t(ts.tv_sec) * kNsPerS + ts.tv_nsec;
}

void sleepUntil(std::int64_t ns) {
    timespec ts{time_t(ns / kNsPerS), long(ns % kNsPerS)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
}

}  // namespace

void LatenessHistogram::add(double us) {
    const auto bin = std::size_t(std::clamp(us, 0.0, double(bins_.size() - 1)));
    ++bins_[bin];
    ++count_;
    max_ = std::max(max_, us);
}

double LatenessHistogram::percentile(double p) const {
    if (count_ == 0) return 0;
    const auto want = std::uint64_t(std::ceil(std::clamp(p, 0.0, 100.0) / 100.0 * double(count_)));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < bins_.size(); ++b)
        if ((seen += bins_[b]) >= std::max<std::uint64_t>(want, 1)) return double(b) + 0.5;  // the bin's middle
    return max_;
}

RateLoop::RateLoop(double hz) : period_(1.0 / hz) {}

bool RateLoop::requestRealtime(int priority) {
    sched_param sp{};
    sp.sched_priority = priority;
    return pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
}

void RateLoop::run(const std::function<bool(const LoopTick&)>& body) {
    const ThreadTimes times;
    timed_ = times.available();
    const ThreadTime first = times.now();
    const std::int64_t period = std::llround(period_ * kNsPerS), start = nowNs();
    std::int64_t k = 0, previous = start;
    for (;;) {
        const std::int64_t due = start + k * period;
        sleepUntil(due);
        const std::int64_t woke = nowNs();
        if (woke - due >= period) ++late_;             // started a whole period or more late
        if (woke - due >= kCatchUpPeriods * period) {  // a stall: skip to the newest deadline
            const std::int64_t skip = (woke - due) / period;
            missed_ += std::uint64_t(skip);
            k += skip;
            // A body slower than the period would otherwise never sleep: under SCHED_FIFO that
            // starves everything else on the core. A tenth of a period leaves it to others.
            sleepUntil(nowNs() + period / 10);
        }
        const std::int64_t deadline = start + k * period;
        LoopTick t{ticks_, 1e-9 * double(deadline - start), 1e-9 * double(deadline - previous),
                   1e-3 * double(woke - deadline)};
        previous = deadline;
        histogram_.add(t.lateUs);
        recentUs_.push_back(t.lateUs);
        if (recentUs_.size() > std::size_t(std::llround(1.0 / period_))) recentUs_.pop_front();
        ++ticks_;
        elapsedS_ = 1e-9 * double(woke - start);
        const ThreadTime before = times.now();
        const bool more = body(t);
        const ThreadTime after = times.now();
        const std::int64_t work = after.cpuNs - before.cpuNs,
                           blocked = (after.wallNs - before.wallNs) - work - (after.waitingNs - before.waitingNs);
        workNs_ += work;
        if (after.majorFaults > before.majorFaults) {
            pagingNs_ += std::max<std::int64_t>(blocked, 0);
        } else {
            blockedNs_ += std::max<std::int64_t>(blocked, 0);
            blockedLongestNs_ = std::max(blockedLongestNs_, blocked);
        }
        waitingNs_ = after.waitingNs - first.waitingNs;
        if (!more) return;
        ++k;
    }
}

PeriodStats RateLoop::whole() const {
    PeriodStats s;
    s.ticks = ticks_;
    s.late = late_;
    s.missed = missed_;
    s.rateHz = elapsedS_ > 0 ? double(ticks_ > 0 ? ticks_ - 1 : 0) / elapsedS_ : 0;
    s.p50Us = histogram_.percentile(50);
    s.p99Us = histogram_.percentile(99);
    s.maxUs = histogram_.max();
    s.timed = timed_;
    s.workMs = 1e-6 * double(workNs_);
    s.blockedMs = 1e-6 * double(blockedNs_);
    s.pagingMs = 1e-6 * double(pagingNs_);
    s.waitingMs = 1e-6 * double(waitingNs_);
    s.blockedLongestUs = 1e-3 * double(blockedLongestNs_);
    return s;
}

PeriodStats RateLoop::recent() const {
    PeriodStats s = whole();
    if (recentUs_.empty()) return s;
    std::vector<double> v(recentUs_.begin(), recentUs_.end());
    const auto at = [&](double p) {
        const auto k = std::size_t(std::lround(p / 100.0 * double(v.size() - 1)));
        std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
        return v[k];
    };
    s.p50Us = at(50);
    s.p99Us = at(99);
    s.maxUs = *std::max_element(v.begin(), v.end());
    return s;
}

}  // namespace bop::haptic
