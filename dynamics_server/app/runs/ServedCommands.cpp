#include "app/runs/ServedCommands.hpp"

#include "server/InboundRanges.hpp"

#include <filesystem>

namespace bop::app {
namespace {

protocol::CommandReply answer(const protocol::Command& c, protocol::ReplyStatus s, long long step,
                              std::string why = {}) {
    protocol::CommandReply r;
    r.requestId = c.requestId;
    r.status = s;
    r.step = std::uint64_t(std::max(0LL, step));
    r.message = why.substr(0, protocol::kMaxTextBytes);  // a reply may not exceed its cap
    return r;
}

}  // namespace

protocol::CommandReply apply(const protocol::Command& c, ClientControls& controls, core::Run& run,
                             const protocol::SceneInfo& scene) {
    using protocol::ReplyStatus;
    const long long next = run.stepNumber();
    const int speciesCount = int(scene.species.size());
    if (const auto why = protocol::refuseCommand(c, scene)) return answer(c, ReplyStatus::Rejected, next, *why);
    core::Command rc;
    try {
        if (const auto* seed = std::get_if<protocol::SeedParticle>(&c.body)) {
            rc = core::SeedCommand{seed->species, seed->position};
        } else if (const auto* birth = std::get_if<protocol::SetBirth>(&c.body)) {
            rc = core::BirthCommand{birth->species, birth->enabled};
        } else if (const auto* p = std::get_if<protocol::SetParameter>(&c.body)) {
            const std::string& n = p->name;
            if (n == "lj" || n == "co_normal" || n == "co_planar") {
                const core::WeightTable table = n == "lj"          ? core::WeightTable::Lj
                                                : n == "co_normal" ? core::WeightTable::CoNormal
                                                                   : core::WeightTable::CoPlanar;
                rc = core::WeightCommand{table, p->speciesA, p->speciesB, p->value};
            } else if (n == "k0" || n == "k1") {  // within their ranges: the decoder checked
                core::ProbeCommand probe{run.paramsAhead().probe};
                (n == "k0" ? probe.probe.params.k0 : probe.probe.params.k1) = p->value;
                rc = probe;
            } else if (n == "drag_v" || n == "drag_w") {
                if (p->speciesA < 1 || p->speciesA > speciesCount)
                    return answer(c, ReplyStatus::Rejected, next, "no species " + std::to_string(p->speciesA));
                const core::Drag d = run.paramsAhead().drag[std::size_t(p->speciesA)];
                rc = core::DragCommand{p->speciesA, n == "drag_v" ? p->value : d.v, n == "drag_w" ? p->value : d.w};
            } else {
                return answer(c, ReplyStatus::Unsupported, next, "unknown parameter '" + n + "'");
            }
        } else if (const auto* cut = std::get_if<protocol::Cut>(&c.body)) {
            rc = core::CutCommand{cut->from, cut->to, cut->radius};
        } else if (const auto* r = std::get_if<protocol::RunControl>(&c.body)) {
            if (r->action == protocol::RunAction::Pause)
                controls.paused = true;
            else if (r->action == protocol::RunAction::Resume)
                controls.paused = false, controls.singleSteps = 0;
            else
                controls.singleSteps += r->steps;
            return answer(c, ReplyStatus::Ok, next);
        } else {
            return answer(c, ReplyStatus::Unsupported, next, "not supported by this server yet");
        }
        const auto* seed = std::get_if<core::SeedCommand>(&rc);
        const auto* birth = std::get_if<core::BirthCommand>(&rc);
        if (const int species = seed    ? seed->species
                                : birth ? birth->species
                                        : 1;
            species < 1 || species > speciesCount)
            return answer(c, ReplyStatus::Rejected, next, "no species " + std::to_string(species));
        run.submit(rc);
    } catch (const std::invalid_argument& e) {
        return answer(c, ReplyStatus::Rejected, next, e.what());
    }
    return answer(c, ReplyStatus::Ok, next);
}

protocol::CommandReply record(const protocol::Command& c, const protocol::Record& r, protocol::ServerFront& front,
                              const std::string& outDir, const std::string& operatorRecording, long long step) {
    using protocol::ReplyStatus;
    if (!operatorRecording.empty())
        return answer(c, ReplyStatus::Rejected, step,
                      "the server records the whole session to " + operatorRecording +
                          " (--record); clients cannot start or stop it");
    try {
        if (!r.start) {
            const std::string file = front.stopRecording();
            return answer(c, ReplyStatus::Ok, step, file.empty() ? "not recording" : "recorded " + file);
        }
        std::string name = r.path.empty() ? "session-step" + std::to_string(step) + ".mcap" : r.path;
        const auto endsWith = [&](const std::string& tail) {
            return name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
        };
        if (name.find('/') != std::string::npos || name.front() == '.' || !endsWith(".mcap"))
            return answer(c, ReplyStatus::Rejected, step,
                          "a plain file name ending in .mcap is expected (it goes into " + outDir + ")");
        const std::string path = outDir + "/" + name;
        if (std::filesystem::exists(path) || std::filesystem::exists(path + ".partial"))
            return answer(c, ReplyStatus::Rejected, step, path + " exists; recordings never replace a file");
        front.startRecording(path);
        return answer(c, ReplyStatus::Ok, step, "recording to " + path);
    } catch (const std::exception& e) {
        return answer(c, ReplyStatus::Failed, step, e.what());
    }
}

}  // namespace bop::app
