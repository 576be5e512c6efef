#pragma once
// What the viewer's panel shows over time, GL-free and clock-free (callers pass times in seconds
// on one steady clock): event rates (frames received, frames drawn) and the histories behind the
// live plots (energy, pressure, probe force against simulation time). The probe's round trip is
// protocol/client/RoundTrip.hpp.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

namespace bop::viz {

// Events per second over a sliding window: (n - 1) / (newest - oldest) of the events within the
// window, so the first seconds read right too; 0 when fewer than two events are in the window.
class RateMeter {
public:
    explicit RateMeter(double windowS = 2.0) : window_(windowS) {}
    void tick(double tS);
    double rateHz(double nowS);

private:
    void expire(double nowS);
    double window_;  // s
    std::deque<double> ticks_;
};

// Histories for the live plots, one sample per new frame. A simulation time below the newest
// one means the server started again: the histories start again too.
struct PlotSample {
    double simTime = 0;       // time
    double energy = 0;        // kinetic + potential, energy
    double pressure = 0;      // energy / length^3
    double probeForce = 0;    // magnitude of the reaction on the probe, force
    double cavityVolume = 0;  // the bag(s) in the map(s) in force, length^3 (keyframed bags: it beats)
};

class PlotHistory {
public:
    explicit PlotHistory(std::size_t capacity = 600) : capacity_(capacity) {}
    void push(const PlotSample& s);
    std::size_t size() const { return samples_.size(); }
    const std::deque<PlotSample>& samples() const { return samples_; }
    // One member as floats, oldest first (for a line plot).
    std::vector<float> series(double PlotSample::*member) const;

private:
    std::size_t capacity_;
    std::deque<PlotSample> samples_;
};

}  // namespace bop::viz
