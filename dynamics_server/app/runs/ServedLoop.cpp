#include "app/runs/ServedLoop.hpp"

#include "core/BloodPressure.hpp"
#include "server/InboundRanges.hpp"

#include <spdlog/spdlog.h>

#include <thread>

namespace bop::app {
namespace {

using Clock = std::chrono::steady_clock;

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

protocol::StateFrame frameOf(core::FrameArrays a, const core::Totals& t, const ClientControls& controls,
                             const core::ProbeState& probe, long long step, double dt, double volume, double stepRate,
                             double realTimeFactor, bool paperEq15) {
    protocol::StateFrame f;
    const std::size_t n = a.species.size();
    f.step = std::uint64_t(step);
    f.simTime = double(step) * dt;
    f.probePosition = probe.position;
    f.probeForce = t.probeReaction;
    f.probeActive = probe.active;
    // In a bag: the blood's pressure (core/BloodPressure.hpp; the scene's formula); in a bulk box: the whole box's.
    const double pressure = t.bloodVolume <= 0 ? (2 * t.kinetic + t.virial) / (3 * volume)
                            : paperEq15
                                ? core::paperEq15Pressure(t.bloodMv2, t.virialVolume, t.bloodCount, t.bloodVolume)
                                : core::virialPressure(t.bloodMv2, t.virialVolume, t.bloodVolume);
    f.stats = {t.kinetic,      t.pairEnergy + t.probeEnergy, pressure,      stepRate, std::uint64_t(n), controls.loop,
               t.cavityVolume, t.keyframe.phase(),           realTimeFactor};
    f.frameParticleCount = std::uint32_t(n);
    f.positions = std::move(a.positions);
    f.normals = std::move(a.normals);
    f.species = std::move(a.species);
    f.ids = std::move(a.ids);
    return f;
}

}  // namespace

ServedLoop::ServedLoop(const Scene& scene, core::Run& run, protocol::ServerFront* front, const ServeOptions& o,
                       std::function<bool()> stopRequested, std::function<void()> afterStep,
                       std::chrono::microseconds idle)
    : scene_(scene),
      model_(run.simulation().model()),
      run_(run),
      front_(front),
      o_(o),
      stopRequested_(std::move(stopRequested)),
      afterStep_(std::move(afterStep)),
      idle_(idle),
      info_(sceneInfoOf(scene, model_, nullptr)),
      volume_(model_.box.size().prod()),
      rateClock_(Clock::now()),
      stepS_(model_.units.physical ? model_.units.toS(model_.integration.dt) : 0),
      pacing_(stepS_ > 0 && scene.realTime && !o.replay),
      paceRef_(Clock::now()) {
    if (o.replay)
        for (const auto& c : o.replay->chunks)
            if (c.frame.chunkIndex == 0) frameSteps_.insert(static_cast<long long>(c.frame.step));
}

void ServedLoop::takeProbe(const protocol::Probe& p) {
    controls_.probeSeq = p.seq;
    controls_.loop = p.loop;
    controls_.clientProbe = true;
    controls_.lastClientProbe = Clock::now();
    front_->probeApplied(p, std::uint64_t(run_.stepNumber()));
    run_.submit(core::ProbeCommand{{p.active, p.position, {p.k0, p.k1}}});
}

ServedLoop::Decision ServedLoop::replayInputs() {
    const long long now = run_.stepNumber();
    const auto& r = *o_.replay;
    for (; nextCommand_ < r.commands.size() && (long long)(r.commands[nextCommand_].reply.step) <= now;
         ++nextCommand_) {
        const auto& rc = r.commands[nextCommand_];
        if ((long long)(rc.reply.step) < now || rc.reply.status != protocol::ReplyStatus::Ok) continue;
        front_->reply({"", rc.command}, apply(rc.command, controls_, run_, info_));
    }
    for (; nextProbe_ < r.probes.size() && (long long)(r.probes[nextProbe_].step) <= now; ++nextProbe_) {
        const protocol::Probe& p = r.probes[nextProbe_].probe;
        if ((long long)(r.probes[nextProbe_].step) != now) continue;
        if (const auto why = protocol::refuseProbe(p, info_)) {  // a recording is a file: not trusted either
            spdlog::warn("replay: probe {} at step {} not applied: {}", p.seq, now, *why);
            continue;
        }
        takeProbe(p);
    }
    controls_.paused = false;  // the recording's steps drive the run
    const bool last = frameSteps_.empty() || now >= *frameSteps_.rbegin();
    return {stopRequested_() || last ? Stopped : Go, true, frameSteps_.count(now + 1) > 0,
            run_.paramsAhead().probe.active};
}

ServedLoop::Decision ServedLoop::decide() {
    for (const auto& pc : front_->takeCommands()) {
        const auto* rec = std::get_if<protocol::Record>(&pc.command.body);
        front_->reply(pc, rec ? record(pc.command, *rec, *front_, o_.outDir, o_.front.recordPath, run_.stepNumber())
                              : apply(pc.command, controls_, run_, info_));
    }
    if (const auto p = front_->takeProbe()) takeProbe(*p);
    if (!front_->anyHaptic()) controls_.loop = {};  // no device loop probing now
    // No probe from any client for a second: a dead client's probe lets go. Taken as a probe like
    // any other, so that a recording holds it and a replay applies it.
    const core::ProbeState& probe = run_.paramsAhead().probe;
    if (controls_.clientProbe && probe.active && Clock::now() - controls_.lastClientProbe > std::chrono::seconds(1)) {
        protocol::Probe off;
        off.seq = controls_.probeSeq;
        off.position = probe.position;
        off.active = false;
        off.k0 = probe.params.k0;
        off.k1 = probe.params.k1;
        takeProbe(off);
    }
    bool step = !controls_.paused || controls_.singleSteps > 0;
    if (step && pacing_ && !keepsPace()) step = false;  // ahead of the wall clock: wait
    if (controls_.paused && controls_.singleSteps > 0 && step) --controls_.singleSteps;
    // No gather while the front still holds a frame: it would only replace it.
    const bool frame = !front_->framePending() && front_->frameDue(Clock::now());
    const bool stop = stopRequested_() || (o_.steps > 0 && done_ >= o_.steps);
    return {stop ? Stopped : Go, step, frame, front_->anyHaptic() || run_.paramsAhead().probe.active};
}

bool ServedLoop::keepsPace() {
    // Simulated time against wall time since the reference: step while not ahead. A pause, or a
    // machine too slow for real time, moves the reference so that no debt builds up: the run
    // never races to catch up by more than kPaceSlack.
    constexpr double kPaceSlack = 0.05;  // s
    const auto now = Clock::now();
    const double wall = std::chrono::duration<double>(now - paceRef_).count();
    if (wall - pacedS_ > kPaceSlack) restartPace(now, kPaceSlack);
    return pacedS_ <= wall;
}

void ServedLoop::restartPace(Clock::time_point now, double behindS) {
    paceRef_ = now - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(pacedS_ + behindS));
}

double ServedLoop::realTimeFactor() const {
    const double wall = std::chrono::duration<double>(Clock::now() - firstPass_).count();
    return done_ > 0 && wall > 0 ? steppedS_ / wall : 0.0;
}

bool ServedLoop::pass() {
    if (firstPass_ == Clock::time_point{}) firstPass_ = Clock::now();
    Decision d;
    if (front_) {
        try {
            d = o_.replay ? replayInputs() : decide();
        } catch (const std::exception& e) {  // rank 0's trouble stops every rank at this pass, cleanly
            error_ = std::string("taking the clients' inputs: ") + e.what();
            d = {Failed, false, false, false};
        }
    }
    const Decision ctl = run_.agree(d);
    if (ctl.stop != Go) {
        if (ctl.stop == Failed && error_.empty()) error_ = "rank 0 stopped the run";
        return false;
    }
    if (ctl.step) {
        if (ctl.publish) run_.energiesNextStep();  // the frame carries them; other steps skip them
        run_.step();                               // core::UnsoundState leaves here, on every rank
        ++done_, ++rateSteps_;
        pacedS_ += stepS_;
        steppedS_ += stepS_;
        if (afterStep_) afterStep_();  // collective: the lifecycle's checkpoints
    } else {
        std::this_thread::sleep_for(idle_);
        if (pacing_ && controls_.paused) restartPace(Clock::now(), 0);  // a pause is not owed
    }
    if (!ctl.feedback && !ctl.publish) return true;
    if (ctl.publish && !run_.energiesCurrent()) run_.refreshForces();  // paused: the same forces, with energies
    const core::Totals t = run_.totals();                              // collective
    if (front_ && ctl.feedback)
        front_->offerFeedback(
            {controls_.probeSeq, std::uint64_t(run_.stepNumber()), t.probeReaction, nowNs(), offerMapEdits()});
    if (ctl.publish) publish(t);
    return true;
}

std::uint32_t ServedLoop::offerMapEdits() {
    const core::Simulation& sim = run_.simulation();
    if (sim.cuts().size() > cutsOffered_ || sim.yields().size() > yieldsOffered_) {
        auto edits = std::make_shared<std::vector<protocol::MapEdit>>();
        if (mapEdits_) *edits = *mapEdits_;
        for (; cutsOffered_ < sim.cuts().size(); ++cutsOffered_) {
            const core::CutCommand& c = sim.cuts()[cutsOffered_];
            edits->push_back({protocol::Cut{c.from, c.to, c.radius}, {}});
        }
        for (; yieldsOffered_ < sim.yields().size(); ++yieldsOffered_) {
            const std::vector<std::uint64_t>& y = sim.yields()[yieldsOffered_];
            for (std::size_t i = 0; i < y.size(); i += protocol::kMaxEditVoxels)
                edits->push_back({{},
                                  {y.begin() + std::ptrdiff_t(i),
                                   y.begin() + std::ptrdiff_t(std::min(i + protocol::kMaxEditVoxels, y.size()))}});
        }
        mapEdits_ = std::move(edits);
        front_->setMapEdits(mapEdits_);
    }
    return mapEdits_ ? std::uint32_t(mapEdits_->size()) : 0;
}

void ServedLoop::publish(const core::Totals& t) {
    core::FrameArrays arrays;
    if (front_) {  // the memory of a frame the front has sent
        protocol::StateFrame spare = front_->takeSpareFrame();
        arrays = {std::move(spare.positions), std::move(spare.normals), std::move(spare.species), std::move(spare.ids)};
    }
    run_.gatherFrame(arrays);  // collective
    if (!front_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - rateClock_).count();
    if (elapsed > 0.5) stepRate_ = double(rateSteps_) / elapsed, rateSteps_ = 0, rateClock_ = Clock::now();
    if (o_.replay)  // a replay is compared frame by frame: none may be replaced unsent
        while (front_->framePending()) std::this_thread::sleep_for(std::chrono::microseconds(200));
    front_->setParticleCount(arrays.species.size());
    front_->offerFrame(frameOf(std::move(arrays), t, controls_, run_.paramsAhead().probe, run_.stepNumber(),
                               model_.integration.dt, volume_, stepRate_, stepRate_ * stepS_,
                               scene_.pressure && scene_.pressure->paperEq15));
}

}  // namespace bop::app
