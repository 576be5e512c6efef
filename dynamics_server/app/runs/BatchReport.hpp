#pragma once
// What a batch run prints: progress lines with rates, per-phase timings, and a summary in the
// form of the paper's Table 1 (surface, volume and total particles, steps per second).
#include "core/Simulation.hpp"

#include <chrono>
#include <ostream>

namespace bop::app {

class BatchReport {
public:
    BatchReport(std::ostream& os, const core::Model& model) : os_(os), model_(model) {}
    void progress(const core::Simulation& sim, long long done, long long total,
                  std::chrono::steady_clock::time_point start);
    void summary(const core::Simulation& sim, long long steps, double seconds);

private:
    std::ostream& os_;
    const core::Model& model_;
};

// Surface and volume particle counts.
std::pair<std::size_t, std::size_t> countKinds(const core::Model& model, const core::Particles& p);

}  // namespace bop::app
