#pragma once
// What a batch run prints, at one process and at N ranks alike: progress lines with rates,
// per-phase timings, and a summary in the form of the paper's Table 1 (surface, volume and total
// particles, steps per second), with the ranks' halo, balance and exchange figures when there
// are several. Collective calls (the totals are reductions); rank 0 prints.
#include "core/Run.hpp"

#include <chrono>
#include <ostream>

namespace bop::app {

class BatchReport {
public:
    BatchReport(std::ostream& os, const core::Run& run) : os_(os), run_(run) {}
    // `done` of `total` steps since `start`. Collective.
    void progress(long long done, long long total, std::chrono::steady_clock::time_point start);
    // After `steps` steps in `seconds`. Collective.
    void summary(long long steps, double seconds);

private:
    void phases(long long steps);  // this process's phase times and pair lists
    std::ostream& os_;
    const core::Run& run_;
};

}  // namespace bop::app
