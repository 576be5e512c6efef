#pragma once
// Clock-free: callers pass times in seconds on one steady clock.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

namespace bop::protocol {

// Probe round trips: the time from sending probe `seq` to the first feedback that names it.
// Feedback repeats a sequence number every step until a newer probe is applied; only the first
// counts. Keeps the newest `capacity` round trips for percentiles.
class RoundTrip {
public:
    explicit RoundTrip(std::size_t capacity = 512) : capacity_(capacity) {}
    void sent(std::uint64_t seq, double tS);
    void feedback(std::uint64_t seq, double tS);
    std::size_t count() const { return samples_.size(); }
    double percentileMs(double p) const;  // p in 0..100; 0 when there are none
    double lastMs() const { return samples_.empty() ? 0 : samples_.back(); }

private:
    std::size_t capacity_;
    std::deque<std::pair<std::uint64_t, double>> pending_;  // (seq, sent at), oldest first
    std::deque<double> samples_;                            // ms
};

}  // namespace bop::protocol
