#pragma once
// The device loop's clock (docs/haptics.md): tick k is due at start + k * period and the thread
// sleeps to it with clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), so lateness never adds
// up. A tick up to four periods late is followed at once by the next ones until the loop is on
// time again, so the rate holds; after a longer stall the deadlines in between are skipped and
// counted as missed, rather than run in a burst. Statistics of the period error (how late each
// tick woke) for the whole run and for the newest second, and of where the thread's time went
// (its work, blocked, waiting for a CPU). Asks for real-time scheduling (SCHED_FIFO) where the
// system permits it.
#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

namespace bop::haptic {

struct LoopTick {
    std::uint64_t index = 0;  // 0, 1, 2, ... (skipped deadlines are not ticks)
    double tS = 0;            // the tick's deadline, s since the start
    double dtS = 0;           // since the previous tick's deadline, s (the period, or more after a miss)
    double lateUs = 0;        // how late the thread woke, microseconds
};

struct PeriodStats {
    double rateHz = 0;                       // ticks per second
    double p50Us = 0, p99Us = 0, maxUs = 0;  // period error (lateness), microseconds
    std::uint64_t ticks = 0;                 // ticks run
    std::uint64_t late = 0;                  // ticks that started a whole period or more late
    std::uint64_t missed = 0;                // deadlines skipped after stalls (no tick ran for them)
    // Where the loop thread's time went (ThreadTimes.hpp; all 0 where the kernel keeps no
    // schedstat, then `timed` is false): the ticks' own work on a CPU, the ticks' work blocked
    // (not runnable: waiting on something) in ticks without and with a page read from disk (the
    // machine's memory), and the whole run's time runnable but not running (the machine kept the
    // loop from its CPU), ms; the longest block in one tick without a page read, us.
    bool timed = false;
    double workMs = 0, blockedMs = 0, pagingMs = 0, waitingMs = 0, blockedLongestUs = 0;
};

// Period errors in microsecond bins up to 100 ms (later ones in the last bin), for percentiles
// of a whole run in bounded memory.
class LatenessHistogram {
public:
    void add(double us);
    double percentile(double p) const;  // p in 0..100, microseconds
    double max() const { return max_; }
    std::uint64_t count() const { return count_; }

private:
    std::vector<std::uint32_t> bins_ = std::vector<std::uint32_t>(100001, 0);
    std::uint64_t count_ = 0;
    double max_ = 0;
};

class RateLoop {
public:
    explicit RateLoop(double hz);
    // SCHED_FIFO at `priority` for the calling thread; false (and nothing changed) when not permitted.
    static bool requestRealtime(int priority = 80);

    // Calls body once per tick until it returns false.
    void run(const std::function<bool(const LoopTick&)>& body);

    PeriodStats whole() const;   // since run() began
    PeriodStats recent() const;  // lateness percentiles of the newest second; rate and counts since the start
    double periodS() const { return period_; }

private:
    double period_;
    LatenessHistogram histogram_;
    std::deque<double> recentUs_;  // the newest ticks' lateness
    std::uint64_t ticks_ = 0, late_ = 0, missed_ = 0;
    double elapsedS_ = 0;
    bool timed_ = false;
    std::int64_t workNs_ = 0, blockedNs_ = 0, pagingNs_ = 0, waitingNs_ = 0, blockedLongestNs_ = 0;
};

}  // namespace bop::haptic
