#include "ServedRun.hpp"

#include "ExtendedXyz.hpp"
#include "codec/DecodeResult.hpp"
#include "parallel/DecomposedRun.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <filesystem>
#include <iostream>
#include <thread>

namespace bop::app {
namespace {

using Clock = std::chrono::steady_clock;
volatile std::sig_atomic_t gStop = 0;
void onSignal(int) { gStop = 1; }

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

// Rank 0's state between passes: what clients asked for and what the run is doing.
struct Desk {
    bool paused = false;
    long long singleSteps = 0;  // steps still to do while paused
    core::ProbeState probe;
    std::uint64_t probeSeq = 0;
    std::vector<std::pair<double, double>> drags;  // per species: beta_v, beta_tau
};

protocol::CommandReply answer(const protocol::Command& c, protocol::ReplyStatus s, long long step, std::string why = {}) {
    protocol::CommandReply r;
    r.requestId = c.requestId;
    r.status = s;
    r.step = std::uint64_t(std::max(0LL, step));
    r.message = why.substr(0, protocol::kMaxTextBytes);  // a reply may not exceed its cap
    return r;
}

// One client command on rank 0: run commands submitted, or the desk changed. The reply says
// the step at which it takes effect (the next step to run) or why not.
protocol::CommandReply apply(const protocol::Command& c, Desk& desk, parallel::DecomposedRun& run, int speciesCount) {
    using protocol::ReplyStatus;
    const long long next = run.stepNumber();
    parallel::Command rc;
    try {
        if (const auto* seed = std::get_if<protocol::SeedParticle>(&c.body)) {
            rc.kind = parallel::Command::Kind::Seed;
            rc.species = seed->species;
            rc.position = seed->position;
        } else if (const auto* birth = std::get_if<protocol::SetBirth>(&c.body)) {
            rc.kind = parallel::Command::Kind::Birth;
            rc.species = birth->species;
            rc.on = birth->enabled;
        } else if (const auto* p = std::get_if<protocol::SetParameter>(&c.body)) {
            const std::string& n = p->name;
            if (n == "lj" || n == "co_normal" || n == "co_planar") {
                rc.kind = parallel::Command::Kind::Weight;
                rc.table = n == "lj" ? parallel::Command::Table::Lj
                         : n == "co_normal" ? parallel::Command::Table::CoNormal : parallel::Command::Table::CoPlanar;
                rc.species = p->speciesA;
                rc.other = p->speciesB;
                rc.value = p->value;
            } else if (n == "k0" || n == "k1") {
                if (!(p->value > 0)) return answer(c, ReplyStatus::Rejected, next, n + " must be > 0");
                (n == "k0" ? desk.probe.params.k0 : desk.probe.params.k1) = p->value;
                rc.kind = parallel::Command::Kind::Probe;
                rc.probe = desk.probe;
            } else if (n == "drag_v" || n == "drag_w") {
                if (p->speciesA < 1 || p->speciesA > speciesCount)
                    return answer(c, ReplyStatus::Rejected, next, "no species " + std::to_string(p->speciesA));
                auto& d = desk.drags[std::size_t(p->speciesA)];
                (n == "drag_v" ? d.first : d.second) = p->value;
                rc.kind = parallel::Command::Kind::Drag;
                rc.species = p->speciesA;
                rc.dragV = d.first;
                rc.dragW = d.second;
            } else {
                return answer(c, ReplyStatus::Unsupported, next, "unknown parameter '" + n + "'");
            }
        } else if (const auto* r = std::get_if<protocol::RunControl>(&c.body)) {
            if (r->action == protocol::RunAction::Pause) desk.paused = true;
            else if (r->action == protocol::RunAction::Resume) desk.paused = false, desk.singleSteps = 0;
            else desk.singleSteps += r->steps;
            return answer(c, ReplyStatus::Ok, next);
        } else {
            return answer(c, ReplyStatus::Unsupported, next, "not supported by this server yet");
        }
        if (rc.kind == parallel::Command::Kind::Seed || rc.kind == parallel::Command::Kind::Birth)
            if (rc.species < 1 || rc.species > speciesCount)
                return answer(c, ReplyStatus::Rejected, next, "no species " + std::to_string(rc.species));
        run.submit(rc);
    } catch (const std::invalid_argument& e) {
        return answer(c, ReplyStatus::Rejected, next, e.what());
    }
    return answer(c, ReplyStatus::Ok, next);
}

protocol::StateFrame frameOf(parallel::FrameArrays a, const parallel::Totals& t, const Desk& desk, long long step,
                             double dt, double volume, double stepRate) {
    protocol::StateFrame f;
    const std::size_t n = a.species.size();
    f.step = std::uint64_t(step);
    f.simTime = double(step) * dt;
    f.probePosition = desk.probe.position;
    f.probeForce = t.probeReaction;
    f.probeActive = desk.probe.active;
    f.stats = {t.kinetic, t.pairEnergy + t.probeEnergy, (2 * t.kinetic + t.virial) / (3 * volume), stepRate,
               std::uint64_t(n)};
    f.frameParticleCount = std::uint32_t(n);
    f.positions = std::move(a.positions);
    f.normals = std::move(a.normals);
    f.species = std::move(a.species);
    f.ids = std::move(a.ids);
    return f;
}

}  // namespace

protocol::SceneInfo sceneInfoOf(const Scene& scene, const GradientMap* map) {
    const core::Model& m = *scene.model;
    protocol::SceneInfo s;
    for (int k = 1; k <= m.speciesCount(); ++k) {
        const core::Species& sp = m.species[std::size_t(k)];
        const auto c = [&](int a) { return std::uint8_t(std::lround(255 * sp.colour[std::size_t(a)])); };
        s.species.push_back({sp.name.substr(0, protocol::kMaxNameBytes),
                             m.isSurface(k) ? protocol::SpeciesKind::Surface : protocol::SpeciesKind::Volume,
                             {c(0), c(1), c(2), 255}});
    }
    s.boxLo = m.box.lo;
    s.boxHi = m.box.hi;
    if (map) {
        const Dims& d = map->wholeDims();
        s.gridOriginMm = map->grid.originMm;
        s.gridDims = {d.nx, d.ny, d.nz};
        s.voxelSizeMm = map->grid.voxelMm;
        s.r0Voxels = map->r0Voxels;
    }
    s.dt = m.integration.dt;
    s.units = "length: simulation units (r0 = sqrt 3); time: simulation units; force: simulation units; mass 1";
    return s;
}

int runServed(const Scene& scene, DecomposedStart start, const ServeOptions& o) {
    const core::Model& model = *scene.model;
    const GradientMap* header = start.options.map ? &start.options.map->header : nullptr;
    protocol::SceneInfo info = sceneInfoOf(scene, header);
    parallel::DecomposedRun run(scene.model, start.particles, std::move(start.options));
    const bool root = run.rank() == 0;
    run.setProbe(scene.probe);
    run.setEnergyEvery(1);  // frames carry the energies
    run.refreshForces();
    std::signal(SIGINT, onSignal);
    std::signal(SIGTERM, onSignal);

    std::unique_ptr<protocol::ServerFront> front;
    Desk desk;
    desk.probe = scene.probe;
    for (const auto& s : model.species) desk.drags.emplace_back(s.dragV, s.dragW);
    if (root) {
        info.particleCount = start.particles.size();
        front = std::make_unique<protocol::ServerFront>(o.front, info);
        // Tests and scripts read this line for the ports.
        std::cout << "listening on " << front->controlEndpoint() << " (frames on port " << front->framePort() << ")"
                  << std::endl;
        if (o.waitForClient) {
            spdlog::info("waiting for a client (--wait-for-client)");
            while (!gStop && !front->waitForClient(std::chrono::milliseconds(200))) {}
        }
    }
    // Replayed inputs (ServeOptions::replay), by step.
    std::size_t nextCommand = 0, nextProbe = 0;
    std::set<long long> frameSteps;
    if (o.replay)
        for (const auto& c : o.replay->chunks)
            if (c.frame.chunkIndex == 0) frameSteps.insert(static_cast<long long>(c.frame.step));
    const auto takeProbe = [&](const protocol::Probe& p) {
        desk.probe.active = p.active;
        desk.probe.position = p.position;
        desk.probe.params = {p.k0, p.k1};
        desk.probeSeq = p.seq;
        front->probeApplied(p, std::uint64_t(run.stepNumber()));
        parallel::Command c;
        c.probe = desk.probe;
        run.submit(c);
    };
    const auto replayInputs = [&]() -> std::array<double, 4> {
        const long long now = run.stepNumber();
        const auto& r = *o.replay;
        for (; nextCommand < r.commands.size() && (long long)(r.commands[nextCommand].reply.step) <= now; ++nextCommand) {
            const auto& rc = r.commands[nextCommand];
            if ((long long)(rc.reply.step) < now || rc.reply.status != protocol::ReplyStatus::Ok) continue;
            front->reply({"", rc.command}, apply(rc.command, desk, run, model.speciesCount()));
        }
        for (; nextProbe < r.probes.size() && (long long)(r.probes[nextProbe].step) <= now; ++nextProbe)
            if ((long long)(r.probes[nextProbe].step) == now) takeProbe(r.probes[nextProbe].probe);
        desk.paused = false;  // the recording's steps drive the run
        const bool last = frameSteps.empty() || now >= *frameSteps.rbegin();
        return {gStop || last ? 1.0 : 0.0, 1.0, frameSteps.count(now + 1) ? 1.0 : 0.0, desk.probe.active ? 1.0 : 0.0};
    };
    const double volume = model.box.size().prod();
    long long done = 0;
    auto rateClock = Clock::now();
    long long rateSteps = 0;
    double stepRate = 0;
    for (;;) {
        std::array<double, 4> ctl{0, 0, 0, 0};  // stop, step, publish, feedback
        if (root && o.replay) {
            ctl = replayInputs();
        } else if (root) {
            for (const auto& pc : front->takeCommands()) front->reply(pc, apply(pc.command, desk, run, model.speciesCount()));
            if (const auto p = front->takeProbe()) takeProbe(*p);
            const bool step = !desk.paused || desk.singleSteps > 0;
            if (desk.paused && desk.singleSteps > 0) --desk.singleSteps;
            // No gather while the front still holds a frame: it would only replace it.
            const bool frame = !front->framePending() && front->frameDue(Clock::now());
            ctl = {gStop || (o.steps > 0 && done >= o.steps) ? 1.0 : 0.0, step ? 1.0 : 0.0, frame ? 1.0 : 0.0,
                   front->anyHaptic() || desk.probe.active ? 1.0 : 0.0};
        }
        ctl = run.agree(ctl);
        if (ctl[0] != 0) break;
        if (ctl[1] != 0) {
            run.step();
            ++done, ++rateSteps;
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        if (ctl[3] == 0 && ctl[2] == 0) continue;
        const parallel::Totals t = run.totals();  // collective
        if (root && ctl[3] != 0) front->offerFeedback({desk.probeSeq, std::uint64_t(run.stepNumber()), t.probeReaction, nowNs()});
        if (ctl[2] == 0) continue;
        parallel::FrameArrays arrays;
        if (root) {  // the memory of a frame the front has sent
            protocol::StateFrame spare = front->takeSpareFrame();
            arrays = {std::move(spare.positions), std::move(spare.normals), std::move(spare.species), std::move(spare.ids)};
        }
        run.gatherFrame(arrays);  // collective
        if (!root) continue;
        const double elapsed = std::chrono::duration<double>(Clock::now() - rateClock).count();
        if (elapsed > 0.5) stepRate = double(rateSteps) / elapsed, rateSteps = 0, rateClock = Clock::now();
        if (o.replay)  // a replay is compared frame by frame: none may be replaced unsent
            while (front->framePending()) std::this_thread::sleep_for(std::chrono::microseconds(200));
        front->setParticleCount(arrays.species.size());
        front->offerFrame(frameOf(std::move(arrays), t, desk, run.stepNumber(), model.integration.dt, volume, stepRate));
    }
    const core::Particles all = run.gather();
    if (!root) return 0;
    front->finish();  // the recording, if any, is complete from here
    const protocol::FrontStats s = front->stats();
    front.reset();
    if (!o.front.recordPath.empty())
        std::cout << (s.recordError.empty() ? "recorded the session in " + o.front.recordPath
                                            : "recording stopped early (" + s.recordError + "); what was written is in " +
                                                  o.front.recordPath + ".partial")
                  << "\n";
    std::filesystem::create_directories(o.outDir);
    const std::string finalFile = o.outDir + "/final.xyz";
    std::filesystem::remove(finalFile);
    XyzFrameInfo fi;
    fi.step = run.stepNumber();
    fi.time = double(fi.step) * model.integration.dt;
    fi.boxLo = model.box.lo;
    fi.boxHi = model.box.hi;
    fi.periodic = model.box.periodic;
    appendExtendedXyz(finalFile, all, speciesNames(model), fi);
    std::cout << "served " << done << " steps to " << s.clients << " clients: " << s.framesSent << " frames ("
              << s.bytesSent / 1e6 << " MB, " << s.framesDropped << " replaced before sending), " << s.commands
              << " commands, " << s.probes << " probes, " << s.malformed << " malformed messages refused ("
              << s.oversized << " oversized), " << s.peersRefused << " peers refused (CURVE key not allowed)\n";
    spdlog::info("final state: {}", finalFile);
    return 0;
}

}  // namespace bop::app
