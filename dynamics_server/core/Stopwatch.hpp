#pragma once
// Wall time of the step's phases (StepTimes, PhaseTimes): seconds since a steady-clock instant.
#include <chrono>

namespace bop::core {

using PhaseClock = std::chrono::steady_clock;

inline double secondsSince(PhaseClock::time_point t) {
    return std::chrono::duration<double>(PhaseClock::now() - t).count();
}

}  // namespace bop::core
