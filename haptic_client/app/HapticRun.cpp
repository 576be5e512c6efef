#include "app/HapticRun.hpp"

#include "app/HapticLink.hpp"
#include "app/HapticMap.hpp"
#include "app/Traces.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/PythonPlot.hpp"
#include "client/ClientSession.hpp"
#include "client/RoundTrip.hpp"
#include "control/BladeCuts.hpp"
#include "control/MapFollow.hpp"
#include "control/RateLoop.hpp"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>

namespace bop::haptic {
namespace {

using Clock = std::chrono::steady_clock;
volatile std::sig_atomic_t gStop = 0;
void onSignal(int) {
    gStop = 1;
}

double wallS() {
    return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}
std::int64_t wallNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// At most `max` long; nothing when it is not finite (the device is never given NaN).
Eigen::Vector3d clampNorm(const Eigen::Vector3d& f, double max) {
    const double n = f.norm();
    if (!std::isfinite(n)) return Eigen::Vector3d::Zero();
    return n > max ? Eigen::Vector3d(f * (max / n)) : f;
}

void printLoop(const RateLoop& loop, bool realtime) {
    const PeriodStats s = loop.whole();
    std::printf(
        "loop: %llu ticks at %.1f Hz; period error p50 %.1f us, p99 %.1f us, max %.1f us; %llu missed "
        "deadlines; %llu ticks a period or more late; real-time priority: %s\n",
        (unsigned long long)s.ticks, s.rateHz, s.p50Us, s.p99Us, s.maxUs, (unsigned long long)s.missed,
        (unsigned long long)s.late, realtime ? "yes" : "no (not permitted)");
    if (s.timed)
        std::printf(
            "loop time: ticks' work %.1f ms on a CPU, blocked %.2f ms (longest in one tick %.1f us); the machine's: "
            "waiting for a CPU %.1f ms, blocked on pages read from disk %.2f ms\n",
            s.workMs, s.blockedMs, s.blockedLongestUs, s.waitingMs, s.pagingMs);
    else
        std::printf("loop time: not measured (no /proc/thread-self/schedstat on this kernel)\n");
}

bool scripted(const std::string& device) {
    return device.rfind("sim:", 0) == 0;
}

}  // namespace

int runLoopOnly(const RunOptions& o) {
    Workspace w;  // identity-like: 0.1 length per mm around the origin
    DeviceOptions script = o.script;
    script.target = o.target.value_or(Eigen::Vector3d::Zero());
    std::unique_ptr<Device> device = makeDevice(o.device, script, w, o.limits);
    ForceModel model(o.model);
    RateLoop loop(o.rateHz);
    const bool realtime = RateLoop::requestRealtime();
    const double seconds = o.seconds > 0 ? o.seconds : 10;
    std::filesystem::create_directories(o.outDir);
    TraceCsv trace(o.outDir + "/haptic-trace.csv");
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::printf("bop-haptic: the device loop alone, %s at %.0f Hz for %.1f s\n", device->name().c_str(), o.rateHz,
                seconds);
    std::fflush(stdout);
    loop.run([&](const LoopTick& t) {
        const Eigen::Vector3d x = w.toScene(device->read(t.tS).positionMm);
        const ForceOutput out = model.tick(t.tS, t.dtS, x);
        const Eigen::Vector3d n = clampNorm(w.forceToDevice(out.force), o.limits.maxForceN);
        device->render(n, t.tS);
        trace.row(t, x, out, n);
        return !gStop && t.tS + loop.periodS() < seconds;
    });
    printLoop(loop, realtime);
    return 0;
}

int runHaptic(const RunOptions& o) {
    protocol::ClientOptions co;
    co.role = protocol::Role::Haptic;
    co.clientName = "bop-haptic";
    co.probeOverUdp = o.udp;
    co.frameRateHz = 1;  // frames are not used here: the slowest tier
    protocol::useCurveKeys(co, o.serverKeyFile, o.clientKeyPrefix);
    HapticLink link(co, o.endpoint, o.reconnectAfterS);
    const protocol::SceneInfo scene = link.connect(std::chrono::seconds(30));
    std::printf("bop-haptic: connected to %s\n", o.endpoint.c_str());
    std::fflush(stdout);
    std::optional<FieldForce> field = downloadField(link.session(), scene, o.fieldStiffness, o.mapMaxMb);
    DeviceOptions script = o.script;
    script.target = o.target ? *o.target : topOfBag(field, scene);
    const UnitSystem& units = scene.unitSystem;
    Workspace w;
    try {
        w = Workspace::forScene(o.limits.workspaceMm, Eigen::AlignedBox3d(scene.boxLo, scene.boxHi), units,
                                o.newtonsPerForce, o.forceScale);
    } catch (const std::invalid_argument& e) {
        throw Error("--newtons-per-force", e.what());
    }
    if (o.workspaceScale > 0) w.scale = o.workspaceScale;
    if (o.workspaceCentre) w.sceneCentre = *o.workspaceCentre;
    std::unique_ptr<Device> device = makeDevice(o.device, script, w, o.limits);
    // The coupling as the device renders it, N/mm, within what the device renders stably.
    ForceModelParams params = o.model;
    const double newtonsPerMm = w.newtonsPerForce * w.scale;  // per (force / length)
    // A tissue in newtons: felt through the stiffest coupling the device renders (in series with
    // the tissue, the softer of the two is what the hand feels), its force from the server alone.
    const double fieldStiffness = units.physical && !o.fieldGiven ? 0.0 : o.fieldStiffness;
    if (units.physical && !o.couplingGiven) {
        params.stiffness = device->limits().maxStiffnessNPerMm / newtonsPerMm;
        std::printf("bop-haptic: coupling %.3g force/length, the device's stiffest (%.3g N/mm); no map field\n",
                    params.stiffness, device->limits().maxStiffnessNPerMm);
    }
    if (params.stiffness * newtonsPerMm > device->limits().maxStiffnessNPerMm * (1 + 1e-12)) {
        params.stiffness = device->limits().maxStiffnessNPerMm / newtonsPerMm;
        std::printf("bop-haptic: coupling stiffness lowered to %.3g force/length (%.3g N/mm, the device's most)\n",
                    params.stiffness, device->limits().maxStiffnessNPerMm);
    }
    // Cutting: strokes of the hand's path sent without waiting, the field's map cut alike; the
    // field's map follows the server's edits too (other clients' cuts, plasticity's yields).
    BladePath blade(o.cutRadius);
    std::optional<FieldCutter> cutter;
    std::optional<MapFollower> follower;
    if (field) cutter.emplace(*field, SurfaceGeometryParams{}), follower.emplace(*cutter);
    std::uint64_t strokes = 0, strokesDropped = 0;
    ForceModel model(params, field && fieldStiffness > 0
                                 ? std::function<Eigen::Vector3d(const Eigen::Vector3d&)>(std::cref(*field))
                                 : std::function<Eigen::Vector3d(const Eigen::Vector3d&)>());
    const double k0 = o.k0 > 0 ? o.k0 : scene.tunables.k0, k1 = o.k1 > 0 ? o.k1 : scene.tunables.k1;
    std::filesystem::create_directories(o.outDir);
    TraceCsv trace(o.outDir + "/haptic-trace.csv");
    // A scene with materials: the curve in the device's mm and N, else in the scene's units.
    StiffnessCurve curve = units.physical
                               ? StiffnessCurve(w.toDevice(script.target), w.rotation.conjugate() * script.inward,
                                                0.05 * units.lengthMm, true)
                               : StiffnessCurve(script.target, script.inward, 0.05);
    protocol::RoundTrip roundTrip(1u << 20);
    RateLoop loop(o.rateHz);
    const bool realtime = RateLoop::requestRealtime();
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);
    std::printf(
        "bop-haptic: %s at %.0f Hz; target %.3f,%.3f,%.3f; %.4g length per mm, %.3g N per force unit (%s); "
        "coupling %.3g force/length, field %.3g force/length\n",
        device->name().c_str(), o.rateHz, script.target.x(), script.target.y(), script.target.z(), w.scale,
        w.newtonsPerForce,
        units.physical ? (o.forceScale == 1 ? "the tissue's newtons" : "the tissue's newtons, scaled by --force-scale")
                       : "--newtons-per-force: the scene has no materials",
        params.stiffness, field ? fieldStiffness : 0.0);
    std::fflush(stdout);
    std::uint64_t seq = 0, feedbacks = 0;
    double largestN = 0;
    protocol::LoopStats stats;
    Eigen::Vector3d lastProxy = script.target;
    // However the loop ends (its end, a signal, an exception): the device is let go and the
    // probe switched off, then a moment for the message to leave before the socket closes.
    struct LetGo {
        std::function<void()> f;
        ~LetGo() { f(); }
    } letGo{[&] {
        device->render(Eigen::Vector3d::Zero(), 0);
        try {
            link.session().sendProbe(
                {++seq, wallNs(), lastProxy.allFinite() ? lastProxy : script.target, false, k0, k1, stats, {0, 0, 0}});
            link.session().waitFeedback(Clock::now() + std::chrono::milliseconds(50));
        } catch (const std::exception&) {  // the server is gone: nothing to switch off
        }
    }};
    loop.run([&](const LoopTick& t) {
        const DeviceState state = device->read(t.tS);
        const Eigen::Vector3d x = w.toScene(state.positionMm);
        const auto fb = link.session().pollFeedback();
        if (fb) {
            model.feedback(fb->force, t.tS);
            roundTrip.feedback(fb->probeSeq, wallS());
            ++feedbacks;
        }
        if (link.tick(t.tS, fb.has_value()) && follower) follower->restart();
        if (follower) follower->tick(link.session(), t.tS, fb ? std::optional(fb->mapEdits) : std::nullopt);
        const ForceOutput out = model.tick(t.tS, t.dtS, x);
        lastProxy = out.proxy;
        const Eigen::Vector3d n = clampNorm(w.forceToDevice(out.force), device->limits().maxForceN);
        device->render(n, t.tS);
        largestN = std::max(largestN, n.norm());
        if (t.index % 100 == 0) {
            const PeriodStats r = loop.recent();
            stats = {float(r.rateHz), float(r.p99Us), r.missed + r.late};
        }
        const bool cutting = o.cut || (o.cutButton >= 0 && ((state.buttons >> o.cutButton) & 1u));
        if (const std::optional<Stroke> s = blade.tick(t.tS, cutting, x)) {  // the hand's, not the proxy's
            protocol::Command c;
            c.requestId = ++strokes;
            c.body = protocol::Cut{s->from, s->to, s->radius};
            if (!link.session().postCommand(c)) ++strokesDropped;
            if (cutter) cutter->push(*s);
        }
        protocol::Probe p{++seq, wallNs(), out.proxy, true, k0, k1, stats, w.forceToScene(n)};
        link.session().sendProbe(p);
        roundTrip.sent(seq, wallS());
        trace.row(t, x, out, n);
        if (scripted(o.device))  // as felt: after the device's clamp
            units.physical ? curve.add(w.toDevice(x), n) : curve.add(x, w.forceToScene(n));
        return !gStop && (o.seconds > 0 ? t.tS + loop.periodS() < o.seconds : !state.finished);
    });
    printLoop(loop, realtime);
    std::printf("probe round trip: p50 %.2f ms, p99 %.2f ms, max %.2f ms over %zu probes; %llu feedback messages\n",
                roundTrip.percentileMs(50), roundTrip.percentileMs(99), roundTrip.percentileMs(100), roundTrip.count(),
                (unsigned long long)feedbacks);
    if (link.reconnections() > 0) std::printf("reconnections: %u\n", link.reconnections());
    if (cutter) cutter->drain();
    if (o.cut || o.cutButton >= 0)
        std::printf("cutting: %llu strokes sent (%llu dropped, the send queue full), radius %.3g\n",
                    (unsigned long long)strokes, (unsigned long long)strokesDropped, o.cutRadius);
    if (cutter)
        std::printf(
            "map copy: %zu edits (%llu own strokes, %u of the server's %u), %zu refused%s%s; the slowest %.2f ms "
            "(off the loop)\n",
            cutter->applied(), (unsigned long long)strokes, follower->taken(), follower->known(), cutter->refused(),
            cutter->refused() ? ", the last: " : "", cutter->lastRefusal().c_str(), cutter->slowestMs());
    std::printf("largest force rendered: %.3f N; trace in %s/haptic-trace.csv\n", largestN, o.outDir.c_str());
    if (scripted(o.device) && !curve.points().empty()) {
        curve.writeCsv(o.outDir + "/stiffness.csv");
        const std::string why =
            plotWithMatplotlib("stiffness", {o.outDir + "/stiffness.csv", o.outDir + "/stiffness.png"});
        if (why.empty())
            std::printf("stiffness curve: %s/stiffness.csv and stiffness.png\n", o.outDir.c_str());
        else
            std::printf("stiffness curve: %s/stiffness.csv (stiffness.png not drawn: %s)\n", o.outDir.c_str(),
                        why.c_str());
    }
    return 0;
}

}  // namespace bop::haptic
