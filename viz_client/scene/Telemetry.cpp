#include "scene/Telemetry.hpp"

#include <algorithm>
#include <cmath>

namespace bop::viz {

void RateMeter::expire(double nowS) {
    while (!ticks_.empty() && ticks_.front() < nowS - window_) ticks_.pop_front();
}

void RateMeter::tick(double tS) {
    ticks_.push_back(tS);
    expire(tS);
}

double RateMeter::rateHz(double nowS) {
    expire(nowS);
    if (ticks_.size() < 2 || ticks_.back() <= ticks_.front()) return 0;
    return double(ticks_.size() - 1) / (ticks_.back() - ticks_.front());
}

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

void PlotHistory::push(const PlotSample& s) {
    if (!samples_.empty() && s.simTime < samples_.back().simTime) samples_.clear();
    samples_.push_back(s);
    while (samples_.size() > capacity_) samples_.pop_front();
}

std::vector<float> PlotHistory::series(double PlotSample::*member) const {
    std::vector<float> v;
    v.reserve(samples_.size());
    for (const PlotSample& s : samples_) v.push_back(float(s.*member));
    return v;
}

}  // namespace bop::viz
