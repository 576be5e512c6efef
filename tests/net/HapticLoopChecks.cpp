#include "HapticLoopChecks.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <fstream>
#include <regex>

namespace bop::test {

void checkHapticLoop(const std::string& printed, const std::string& trace, double blockBoundMs) {
    std::smatch loop, time;
    REQUIRE(std::regex_search(printed, loop,
                              std::regex("loop: ([0-9]+) ticks at [0-9.]+ Hz;.* ([0-9]+) missed deadlines; ([0-9]+) "
                                         "ticks a period or more late")));
    REQUIRE(
        std::regex_search(printed, time,
                          std::regex("loop time: ticks' work ([0-9.]+) ms on a CPU, blocked ([0-9.]+) ms \\(longest "
                                     "in one tick ([0-9.]+) us\\); the machine's: waiting for a CPU ([0-9.]+) ms, "
                                     "blocked on pages read from disk ([0-9.]+) ms")));
    const double ticks = std::stod(loop[1]), missed = std::stod(loop[2]);
    const double workMs = std::stod(time[1]), blockedMs = std::stod(time[2]), longestUs = std::stod(time[3]),
                 waitingMs = std::stod(time[4]), pagingMs = std::stod(time[5]);
    // The last tick's deadline, ms since the start, from the trace (one row per tick).
    std::ifstream in(trace);
    std::string line, last;
    while (std::getline(in, line))
        if (!line.empty()) last = line;
    REQUIRE(!last.empty());
    const double lastMs = std::round(1000 * std::stod(last.substr(0, last.find(','))));
    INFO(loop[0] << "; " << time[0] << "; last deadline at " << lastMs << " ms");
    CHECK(ticks + missed == lastMs + 1);
    CHECK(longestUs < 1000 * blockBoundMs);
    std::printf(
        "haptic loop: %.0f ticks, %.0f missed deadlines; its work %.1f ms, blocked %.2f ms (longest %.1f us "
        "in a tick); the machine's: waiting for a CPU %.1f ms, paging %.2f ms\n",
        ticks, missed, workMs, blockedMs, longestUs, waitingMs, pagingMs);
}

}  // namespace bop::test
