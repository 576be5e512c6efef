#pragma once
// The served run's loop, one pass at a time (runServed drives it; the front fuzzer too). Rank 0
// takes the clients' commands and newest probe from the front (or a recording's, by step), turns
// them into run commands or changes of the client controls, and decides whether to stop, step, publish a frame and
// send feedback; every rank agrees on that decision, steps, and joins the gathers when due. No
// rank waits on a client. Nothing rank 0 meets while taking the inputs escapes: the run stops
// cleanly instead, every rank at the same pass (error()).
#include "app/runs/ServedCommands.hpp"
#include "app/runs/ServedRun.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace bop::app {

class ServedLoop {
public:
    // front: rank 0's (null on the other ranks); stopRequested: rank 0's signal flag, read each pass;
    // afterStep: called after each step on every rank (RunLifecycle::afterStep: the checkpoints
    // and the ventricle's curve); idle: how long a pass without a step (paused) sleeps.
    ServedLoop(const Scene& scene, core::Run& run, protocol::ServerFront* front, const ServeOptions& o,
               std::function<bool()> stopRequested, std::function<void()> afterStep = {},
               std::chrono::microseconds idle = std::chrono::milliseconds(1));

    // One pass; false when the run is to stop (a signal, --steps, the replay's end, or an error on
    // rank 0: error()). core::UnsoundState from a step that ends unsound (on every rank).
    bool pass();

    long long stepsDone() const { return done_; }
    const std::string& error() const { return error_; }  // why rank 0 stopped the run; empty if nothing went wrong
    ClientControls& controls() { return controls_; }
    // Simulated s per wall s since the loop's first pass (0: time in simulation units).
    double realTimeFactor() const;

private:
    enum Stop : int { Go = 0, Stopped = 1, Failed = 2 };  // Decision::stop
    using Decision = core::Run::Decision;
    Decision decide();        // rank 0
    Decision replayInputs();  // rank 0, replaying
    void takeProbe(const protocol::Probe& p);
    void publish(const core::Totals& t);  // collective gather; rank 0 offers the frame
    // Rank 0: the map's edits the run made since the last call (cuts, yields split into pieces of
    // at most protocol::kMaxEditVoxels voxels) join the list the front serves; its length.
    std::uint32_t offerMapEdits();
    bool keepsPace();  // rank 0: the next step is due by the wall clock
    // The pacing's wall-clock reference moved so that the simulated time stands behindS seconds
    // behind the wall clock at `now`.
    void restartPace(std::chrono::steady_clock::time_point now, double behindS);

    const Scene& scene_;
    const core::Model& model_;
    core::Run& run_;
    protocol::ServerFront* front_;
    const ServeOptions& o_;
    std::function<bool()> stopRequested_;
    std::function<void()> afterStep_;
    std::chrono::microseconds idle_;
    protocol::SceneInfo info_;  // the scene's ranges, for replayed inputs (server/InboundRanges.hpp)
    ClientControls controls_;
    std::string error_;
    long long done_ = 0;
    std::size_t nextCommand_ = 0, nextProbe_ = 0;  // replayed inputs (ServeOptions::replay), by step
    std::set<long long> frameSteps_;
    std::shared_ptr<const std::vector<protocol::MapEdit>> mapEdits_;  // rank 0: what the front serves
    std::size_t cutsOffered_ = 0, yieldsOffered_ = 0;                 // of the run's cuts() and yields()
    double volume_ = 0;                                               // the box's, length^3
    std::chrono::steady_clock::time_point rateClock_;
    long long rateSteps_ = 0;
    double stepRate_ = 0;
    // Real time (a scene with materials and [units] real_time): one simulated second per wall
    // second at most (docs/physics.md §8.5).
    double stepS_ = 0;  // a step's simulated time, s; 0: time in simulation units
    bool pacing_ = false;
    std::chrono::steady_clock::time_point paceRef_;  // the wall time at simulated time 0 of the pacing
    double pacedS_ = 0;                              // simulated time stepped since, s

    std::chrono::steady_clock::time_point firstPass_{};  // the loop's first pass
    double steppedS_ = 0;                                // simulated time stepped by the loop, s
};

}  // namespace bop::app
