#include "control/ThreadTimes.hpp"

#include <cinttypes>
#include <cstdio>
#include <ctime>

#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

namespace bop::haptic {

ThreadTimes::ThreadTimes() : fd_(open("/proc/thread-self/schedstat", O_RDONLY | O_CLOEXEC)) {}

ThreadTimes::~ThreadTimes() {
    if (fd_ >= 0) close(fd_);
}

ThreadTime ThreadTimes::now() const {
    ThreadTime t;
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    t.wallNs = std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    // The CPU time from the thread's clock: schedstat's first figure is brought up to date only
    // at the scheduler's events, so it lags behind a running thread.
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    t.cpuNs = std::int64_t(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
    rusage u{};
    if (getrusage(RUSAGE_THREAD, &u) == 0) t.majorFaults = u.ru_majflt;
    if (fd_ < 0) return t;
    char buf[96];
    const ssize_t n = pread(fd_, buf, sizeof buf - 1, 0);  // "CPU_NS WAITING_NS TIMESLICES\n"
    if (n <= 0) return t;
    buf[n] = '\0';
    std::int64_t cpu = 0, waiting = 0;
    if (std::sscanf(buf, "%" SCNd64 " %" SCNd64, &cpu, &waiting) == 2) t.waitingNs = waiting;
    return t;
}

}  // namespace bop::haptic
