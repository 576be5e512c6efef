// bop-netdelay --delay-ms D [--jitter-ms J] [--queue N]: holds the packets an iptables rule
// queues to netfilter queue N (`-j NFQUEUE --queue-num N --queue-bypass`) for D ms (plus jitter) before letting them
// go: scripts/two-host.sh's delay on kernels without tc netem. Runs until SIGINT/SIGTERM, then
// lets every held packet go and prints how many it delayed.
#include "NetDelayQueue.hpp"
#include "bop/common/ToolMain.hpp"

#include <CLI/CLI.hpp>
#include <sched.h>

#include <csignal>
#include <cstdio>

#include <poll.h>

namespace {
volatile std::sig_atomic_t gStop = 0;
void onSignal(int) {
    gStop = 1;
}
}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-netdelay", [&] {
        CLI::App app{
            "bop-netdelay: delays the packets an iptables rule queues to it (-j NFQUEUE --queue-num N "
            "--queue-bypass), for "
            "scripts/two-host.sh on kernels without tc netem. Needs root."};
        double delayMs = 0, jitterMs = 0;
        std::uint16_t queue = 0;
        std::uint32_t seed = 1;
        app.add_option("--delay-ms", delayMs, "added latency, ms")->required()->check(CLI::Range(0.0, 10000.0));
        app.add_option("--jitter-ms", jitterMs, "standard deviation of a normal spread around it, ms (cut at 0)")
            ->check(CLI::Range(0.0, 10000.0));
        app.add_option("--queue", queue, "the netfilter queue number");
        app.add_option("--seed", seed, "seed of the jitter");
        CLI11_PARSE(app, argc, argv);
        bop::netdelay::DelayQueue q(queue, delayMs, jitterMs, seed);
        sched_param p{};
        p.sched_priority = 10;  // on time under load where permitted; fine without
        const bool realtime = sched_setscheduler(0, SCHED_FIFO, &p) == 0;
        std::signal(SIGINT, onSignal);
        std::signal(SIGTERM, onSignal);
        std::printf("bop-netdelay: queue %u, delay %.3g ms, jitter %.3g ms, real-time priority: %s; ready\n",
                    unsigned(queue), delayMs, jitterMs, realtime ? "yes" : "no");
        std::fflush(stdout);
        using bop::netdelay::Clock;
        while (!gStop) {
            const Clock::time_point due = q.nextDue();
            const auto wait = due == Clock::time_point::max()
                                  ? std::chrono::nanoseconds(100'000'000)
                                  : std::max(std::chrono::nanoseconds(0), due - Clock::now());
            const timespec ts{time_t(wait.count() / 1'000'000'000), long(wait.count() % 1'000'000'000)};
            pollfd fd{q.fd(), POLLIN, 0};
            if (ppoll(&fd, 1, &ts, nullptr) > 0) q.receive();
            q.release(Clock::now());
        }
        const auto& s = q.stats();
        std::printf("bop-netdelay: %llu packets delayed; at most %.3f ms late; %llu queue overflows\n",
                    (unsigned long long)s.delayed, s.largestLateMs, (unsigned long long)s.overflows);
        return 0;
    });
}
