#pragma once
// Where the calling thread's time went: on a CPU (its CPU-time clock), and runnable but waiting
// for one (the kernel's scheduler statistics, /proc/thread-self/schedstat, proc(5)). The rest of
// the wall time the thread was not runnable: it slept or blocked. The device loop reads it
// around each tick's work, so that its summary says how long the work ran, how long it blocked
// (a loop that waited on the network would block), and how long the machine kept it from
// running: the deadlines it missed are the machine's, or its own. A block in which the thread
// faulted a page in from disk is the machine's memory, not the loop's: counted apart.
#include <cstdint>

namespace bop::haptic {

struct ThreadTime {
    std::int64_t wallNs = 0;     // CLOCK_MONOTONIC
    std::int64_t cpuNs = 0;      // on a CPU, since the thread started
    std::int64_t waitingNs = 0;  // runnable, waiting for a CPU, since the thread started (0 without schedstat)
    long majorFaults = 0;        // page faults that read from disk (getrusage), since the thread started
};

class ThreadTimes {
public:
    ThreadTimes();  // opens the calling thread's schedstat; the times are read on that thread
    ~ThreadTimes();
    ThreadTimes(const ThreadTimes&) = delete;
    ThreadTimes& operator=(const ThreadTimes&) = delete;

    bool available() const { return fd_ >= 0; }  // false where the kernel keeps no schedstat
    ThreadTime now() const;

private:
    int fd_ = -1;
};

}  // namespace bop::haptic
