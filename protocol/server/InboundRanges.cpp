#include "server/InboundRanges.hpp"

#include <cstdio>
#include <variant>

namespace bop::protocol {
namespace {

std::string vec(const Eigen::Vector3d& v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", v.x(), v.y(), v.z());
    return text;
}

std::optional<std::string> species(int s, int lowest, const SceneInfo& scene, const char* field) {
    const int n = int(scene.species.size());
    if (s >= lowest && s <= n) return std::nullopt;
    return std::string(field) + ": species " + std::to_string(s) + " outside " + std::to_string(lowest) + ".." +
           std::to_string(n) + " (the scene's species)";
}

std::optional<std::string> check(const SeedParticle& b, const SceneInfo& scene) {
    if (auto why = species(b.species, 1, scene, "Command.SeedParticle.species")) return why;
    if (Eigen::AlignedBox3d(scene.boxLo, scene.boxHi).contains(b.position)) return std::nullopt;
    return "Command.SeedParticle.position: " + vec(b.position) + " outside the box " + vec(scene.boxLo) + ".." +
           vec(scene.boxHi);
}

std::optional<std::string> check(const SetBirth& b, const SceneInfo& scene) {
    return species(b.species, 1, scene, "Command.SetBirth.species");
}

std::optional<std::string> check(const SetParameter& b, const SceneInfo& scene) {
    const std::string& n = b.name;
    if (n == "lj" || n == "co_normal" || n == "co_planar") {
        if (auto why = species(b.speciesA, 1, scene, "Command.SetParameter.species_a")) return why;
        return species(b.speciesB, 1, scene, "Command.SetParameter.species_b");
    }
    if (n == "drag_v" || n == "drag_w") return species(b.speciesA, 1, scene, "Command.SetParameter.species_a");
    return std::nullopt;  // k0, k1: no species; unknown names: Unsupported
}

// A blade within the probe's reach, no wider than the box.
std::optional<std::string> check(const Cut& b, const SceneInfo& scene) {
    const Eigen::AlignedBox3d reach = probeReachBox(scene);
    for (const Eigen::Vector3d* x : {&b.from, &b.to})
        if (!reach.contains(*x))
            return std::string("Command.Cut.") + (x == &b.from ? "from" : "to") + ": " + vec(*x) + " outside " +
                   vec(reach.min()) + ".." + vec(reach.max()) + " (the box grown by twice its largest side)";
    const double widest = (scene.boxHi - scene.boxLo).maxCoeff();
    if (b.radius <= widest) return std::nullopt;
    return "Command.Cut.radius: " + std::to_string(b.radius) + " wider than the box (" + std::to_string(widest) + ")";
}

template <class Body>
std::optional<std::string> check(const Body&, const SceneInfo&) {
    return std::nullopt;  // RunControl: the decoder's ranges; the others: the server decides
}

}  // namespace

Eigen::AlignedBox3d probeReachBox(const SceneInfo& scene) {
    const double margin = 2 * (scene.boxHi - scene.boxLo).maxCoeff();
    return {scene.boxLo.array() - margin, scene.boxHi.array() + margin};
}

std::optional<std::string> refuseProbe(const Probe& p, const SceneInfo& scene) {
    const Eigen::AlignedBox3d reach = probeReachBox(scene);
    if (reach.contains(p.position)) return std::nullopt;
    return "Probe.position: " + vec(p.position) + " outside " + vec(reach.min()) + ".." + vec(reach.max()) +
           " (the box grown by twice its largest side)";
}

std::optional<std::string> refuseCommand(const Command& c, const SceneInfo& scene) {
    return std::visit([&](const auto& body) { return check(body, scene); }, c.body);
}

std::optional<std::string> refuseMapRequest(const MapRequest& r, const SceneInfo& scene) {
    if (r.offset <= scene.mapBytes) return std::nullopt;
    return "MapRequest.offset: " + std::to_string(r.offset) + " beyond the map's " + std::to_string(scene.mapBytes) +
           " bytes";
}

}  // namespace bop::protocol
