#include "ServedRun.hpp"

#include "ServedCommands.hpp"

#include "Checkpoint.hpp"
#include "DecomposedBatch.hpp"
#include "ExtendedXyz.hpp"
#include "core/BloodPressure.hpp"
#include "shape/GradientMapFile.hpp"
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

protocol::StateFrame frameOf(parallel::FrameArrays a, const parallel::Totals& t, const Desk& desk, long long step,
                             double dt, double volume, double stepRate, bool paperEq15) {
    protocol::StateFrame f;
    const std::size_t n = a.species.size();
    f.step = std::uint64_t(step);
    f.simTime = double(step) * dt;
    f.probePosition = desk.probe.position;
    f.probeForce = t.probeReaction;
    f.probeActive = desk.probe.active;
    // In a bag: the blood's pressure (core/BloodPressure.hpp; the scene's formula); in a bulk box: the whole box's.
    const double pressure = t.bloodVolume <= 0 ? (2 * t.kinetic + t.virial) / (3 * volume)
                            : paperEq15     ? core::paperEq15Pressure(t.bloodMv2, t.virialVolume, t.bloodCount, t.bloodVolume)
                                            : core::virialPressure(t.bloodMv2, t.virialVolume, t.bloodVolume);
    f.stats = {t.kinetic, t.pairEnergy + t.probeEnergy, pressure, stepRate, std::uint64_t(n), desk.loop, t.cavityVolume,
               t.keyframe.phase()};
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
    s.probeReach = m.ljParams.rCutR0 * s.r0;
    const int n = m.speciesCount();
    const auto matrix = [&](const core::WeightMatrix& w) {
        std::vector<double> v;
        for (int a = 1; a <= n; ++a)
            for (int b = 1; b <= n; ++b) v.push_back(w(a, b));
        return v;
    };
    s.tunables.k0 = scene.probe.params.k0;
    s.tunables.k1 = scene.probe.params.k1;
    if (std::size_t(n) <= protocol::kMaxTunedSpecies)  // SceneInfo has a size cap
        s.tunables = {matrix(m.lj), matrix(m.coNormal), matrix(m.coPlanar), {}, {}, s.tunables.k0, s.tunables.k1};
    for (int k = 1; k <= n && std::size_t(n) <= protocol::kMaxTunedSpecies; ++k) {
        s.tunables.dragV.push_back(m.species[std::size_t(k)].dragV);
        s.tunables.dragW.push_back(m.species[std::size_t(k)].dragW);
    }
    s.units = "length: simulation units (r0 = sqrt 3); time: simulation units; force: simulation units; mass 1";
    return s;
}

int runServed(const Scene& scene, DecomposedStart start, const ServeOptions& o) {
    const core::Model& model = *scene.model;
    const GradientMap* header = start.options.map ? &start.options.map->header : nullptr;
    protocol::SceneInfo info = sceneInfoOf(scene, header);
    std::optional<CardiacRun> cardiac;  // [pressure]: the curve of a ventricle watched live, written at the end
    const std::optional<GradientMap> mapHeader = header ? std::optional(*header) : std::nullopt;
    parallel::DecomposedRun run(scene.model, start.particles, std::move(start.options));
    if (scene.pressure && mapHeader) cardiac.emplace(scene, *mapHeader, run.frameVolumes());
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
        std::error_code ec;  // the gradient-map cache, for haptic clients to download
        if (scene.shape && !o.front.mapFile.empty() && std::filesystem::is_regular_file(o.front.mapFile, ec)) {
            info.mapBytes = std::filesystem::file_size(o.front.mapFile, ec);
            info.mapKey = shape::hashText(scene.shape->canonical);
        }
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
        desk.loop = p.loop;
        desk.clientProbe = true;
        desk.lastClientProbe = Clock::now();
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
            for (const auto& pc : front->takeCommands()) {
                const auto* rec = std::get_if<protocol::Record>(&pc.command.body);
                front->reply(pc, rec ? record(pc.command, *rec, *front, o.outDir, o.front.recordPath, run.stepNumber())
                                     : apply(pc.command, desk, run, model.speciesCount()));
            }
            if (const auto p = front->takeProbe()) takeProbe(*p);
            if (!front->anyHaptic()) desk.loop = {};  // no device loop probing now
            // No probe from any client for a second: a dead client's probe lets go. Taken as a
            // probe like any other, so that a recording holds it and a replay applies it.
            if (desk.clientProbe && desk.probe.active && Clock::now() - desk.lastClientProbe > std::chrono::seconds(1)) {
                protocol::Probe off;
                off.seq = desk.probeSeq;
                off.position = desk.probe.position;
                off.active = false;
                off.k0 = desk.probe.params.k0;
                off.k1 = desk.probe.params.k1;
                takeProbe(off);
            }
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
            if (cardiac) recordCardiac(*cardiac, run, model);
            if (o.checkpointEvery > 0 && run.stepNumber() % o.checkpointEvery == 0) {
                const core::Particles all = run.gather();  // collective
                if (root) writeCheckpoint(o.outDir + "/checkpoint.xyz", all, model, run.construction(), run.stepNumber());
            }
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
        front->offerFrame(frameOf(std::move(arrays), t, desk, run.stepNumber(), model.integration.dt, volume, stepRate,
                                  scene.pressure && scene.pressure->paperEq15));
    }
    const core::Particles all = run.gather();
    if (!root) return 0;
    std::filesystem::create_directories(o.outDir);
    writeCheckpoint(o.outDir + "/checkpoint.xyz", all, model, run.construction(), run.stepNumber());
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
    const XyzFrameInfo fi = snapshotInfo(model, run.stepNumber());
    appendExtendedXyz(finalFile, all, speciesNames(model), fi);
    std::cout << "served " << done << " steps to " << s.clients << " clients: " << s.framesSent << " frames ("
              << s.bytesSent / 1e6 << " MB, " << s.framesDropped << " replaced before sending), " << s.commands
              << " commands, " << s.probes << " probes, " << s.malformed << " malformed messages refused ("
              << s.oversized << " oversized), " << s.peersRefused << " peers refused (CURVE key not allowed)\n";
    if (cardiac) cardiac->finish(o.outDir, std::cout);
    spdlog::info("final state: {}; checkpoint: {}/checkpoint.xyz", finalFile, o.outDir);
    return 0;
}

}  // namespace bop::app
