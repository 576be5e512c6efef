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
