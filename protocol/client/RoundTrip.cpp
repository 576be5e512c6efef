#include "client/RoundTrip.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace bop::protocol {

void RoundTrip::sent(std::uint64_t seq, double tS) {
    pending_.emplace_back(seq, tS);
    while (pending_.size() > 4096) pending_.pop_front();  // feedback never came for the oldest
}

void RoundTrip::feedback(std::uint64_t seq, double tS) {
    // Probes older than `seq` were replaced before the server applied them: they never get theirs.
    while (!pending_.empty() && pending_.front().first < seq) pending_.pop_front();
    if (pending_.empty() || pending_.front().first != seq) return;  // unknown, or counted already
    samples_.push_back(1000.0 * (tS - pending_.front().second));
    pending_.pop_front();
    while (samples_.size() > capacity_) samples_.pop_front();
}

double RoundTrip::percentileMs(double p) const {
    if (samples_.empty()) return 0;
    std::vector<double> s(samples_.begin(), samples_.end());
    const auto k = std::size_t(std::lround(std::clamp(p, 0.0, 100.0) / 100.0 * double(s.size() - 1)));
    std::nth_element(s.begin(), s.begin() + std::ptrdiff_t(k), s.end());
    return s[k];
}

}  // namespace bop::protocol
