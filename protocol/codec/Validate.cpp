// Semantic rules of each message; see Validate.hpp. Limits that are not in DecodeResult.hpp
// are stated where they are used.
#include "codec/Validate.hpp"

#include "codec/Checker.hpp"
#include "codec/Ranges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <variant>

namespace bop::protocol {

namespace {

using detail::Checker;

constexpr float kMaxFrameRateHz = 10000;       // wanted frame rate, wall Hz
constexpr std::int32_t kMaxGridDim = 1 << 16;  // voxels per axis of a gradient map

std::string count(std::size_t n) {
    return std::to_string(n);
}

bool checkBox(Checker& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const char* field) {
    return c.finite(lo, field) && c.finite(hi, field) &&
           c.require((lo.array() < hi.array()).all(), DecodeError::OutOfRange, field,
                     "lower corner not below upper corner on every axis");
}

bool checkName(Checker& c, const std::string& s, const char* field) {
    return c.require(!s.empty(), DecodeError::MissingField, field, "empty") && c.maxBytes(s, kMaxNameBytes, field);
}

void checkBody(Checker& c, const SeedParticle& b) {
    c.species(b.species, 1, kMaxSpecies, "SeedParticle.species") &&
        c.within(b.position, ranges::kMaxCoordinate, "SeedParticle.position");
}
void checkBody(Checker& c, const Cut& b) {
    c.within(b.from, ranges::kMaxCoordinate, "Cut.from") && c.within(b.to, ranges::kMaxCoordinate, "Cut.to") &&
        c.within(b.radius, 0, ranges::kMaxCoordinate, "Cut.radius") &&
        c.require(b.radius > 0, DecodeError::OutOfRange, "Cut.radius", "not above 0");
}
void checkBody(Checker& c, const SetBirth& b) {
    c.species(b.species, 1, kMaxSpecies, "SetBirth.species");
}
// The value's range by parameter name (schemas/command.fbs lists them); a name this version does
// not know needs a finite value here and is answered Unsupported by the server.
void checkValue(Checker& c, const SetParameter& b) {
    using namespace ranges;
    const std::string& n = b.name;
    if (n == "lj" || n == "co_normal" || n == "co_planar")
        c.within(b.value, 0, kMaxWeight, "SetParameter.value");
    else if (n == "drag_v" || n == "drag_w")
        c.within(b.value, 0, kMaxDrag, "SetParameter.value");
    else if (n == "k0")
        c.within(b.value, kMinProbeK0, kMaxProbeK0, "SetParameter.value");
    else if (n == "k1")
        c.within(b.value, kMinProbeK1, kMaxProbeK1, "SetParameter.value");
    else
        c.finite(b.value, "SetParameter.value");
}
void checkBody(Checker& c, const SetParameter& b) {
    checkName(c, b.name, "SetParameter.name") && c.species(b.speciesA, 0, kMaxSpecies, "SetParameter.species_a") &&
        c.species(b.speciesB, 0, kMaxSpecies, "SetParameter.species_b");
    if (c.ok()) checkValue(c, b);
}
void checkBody(Checker& c, const RunControl& b) {
    c.require(std::uint8_t(b.action) <= std::uint8_t(RunAction::SingleStep), DecodeError::Unsupported,
              "RunControl.action", "unknown action " + std::to_string(int(b.action))) &&
        c.require(b.action != RunAction::SingleStep || (b.steps >= 1 && b.steps <= ranges::kMaxSingleSteps),
                  DecodeError::OutOfRange, "RunControl.steps",
                  std::to_string(b.steps) + " outside 1.." + std::to_string(ranges::kMaxSingleSteps));
}
void checkBody(Checker&, const SwitchMapFrame&) {}  // any frame number; the server knows how many it has
void checkBody(Checker& c, const Checkpoint& b) {
    c.maxBytes(b.path, kMaxPathBytes, "Checkpoint.path");
}
void checkBody(Checker& c, const Record& b) {
    c.maxBytes(b.path, kMaxPathBytes, "Record.path");
}

}  // namespace

bool detail::checkQuantBounds(Checker& c, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    return checkBox(c, lo, hi, "quant_lo/quant_hi") &&
           c.require(lo.cwiseAbs().maxCoeff() <= kMaxBoundMagnitude && hi.cwiseAbs().maxCoeff() <= kMaxBoundMagnitude,
                     DecodeError::OutOfRange, "quant_lo/quant_hi", "beyond the float32 range");
}

Validation validate(const Hello& m) {
    Checker c("Hello");
    c.require(m.protocolVersion >= 1, DecodeError::MissingField, "protocol_version", "absent (0)") &&
        c.require(std::uint8_t(m.role) <= std::uint8_t(Role::Control), DecodeError::Unsupported, "role",
                  "unknown role " + std::to_string(int(m.role))) &&
        c.finite(m.frameRateHz, "frame_rate_hz") &&
        c.require(m.frameRateHz >= 0 && m.frameRateHz <= kMaxFrameRateHz, DecodeError::OutOfRange, "frame_rate_hz",
                  "outside 0.." + std::to_string(int(kMaxFrameRateHz)) + " Hz") &&
        c.maxBytes(m.clientName, kMaxNameBytes, "client_name");
    return c.result();
}

namespace {

// Rate and period error finite, >= 0 and within their ranges (Ranges.hpp).
bool validLoop(Checker& c, const LoopStats& s, const char* field) {
    return c.require(std::isfinite(s.rateHz) && s.rateHz >= 0 && s.rateHz <= ranges::kMaxLoopRateHz &&
                         std::isfinite(s.periodErrorP99Us) && s.periodErrorP99Us >= 0 &&
                         s.periodErrorP99Us <= ranges::kMaxPeriodErrorUs,
                     DecodeError::OutOfRange, field,
                     "rate " + Checker::number(s.rateHz) + " Hz and period error " +
                         Checker::number(s.periodErrorP99Us) + " us must lie in 0.." +
                         Checker::number(ranges::kMaxLoopRateHz) + " and 0.." +
                         Checker::number(ranges::kMaxPeriodErrorUs));
}

// Matrices empty or n x n, per-species arrays empty or n, every value finite, dampings >= 0, k0 > 0.
bool validTunables(Checker& c, const Tunables& t, std::size_t n) {
    const auto sized = [&](const std::vector<double>& v, std::size_t want, const char* field) {
        bool ok = c.require(v.empty() || (v.size() == want && n <= kMaxTunedSpecies), DecodeError::BadLength, field,
                            std::to_string(v.size()) + " values, expected 0 or " + std::to_string(want) +
                                " (and at most " + std::to_string(kMaxTunedSpecies) + " species)");
        for (double x : v) ok = ok && c.finite(x, field);
        return ok;
    };
    bool ok = sized(t.lj, n * n, "tunables.lj") && sized(t.coNormal, n * n, "tunables.co_normal") &&
              sized(t.coPlanar, n * n, "tunables.co_planar") && sized(t.dragV, n, "tunables.drag_v") &&
              sized(t.dragW, n, "tunables.drag_w");
    for (double x : t.dragV) ok = ok && c.require(x >= 0, DecodeError::OutOfRange, "tunables.drag_v", "negative");
    for (double x : t.dragW) ok = ok && c.require(x >= 0, DecodeError::OutOfRange, "tunables.drag_w", "negative");
    return ok && c.finite(t.k0, "tunables.k0") && c.finite(t.k1, "tunables.k1") &&
           c.require(t.k0 > 0, DecodeError::OutOfRange, "tunables.k0", "not > 0");
}

}  // namespace

Validation validate(const SceneInfo& m) {
    Checker c("SceneInfo");
    if (!c.require(m.protocolVersion >= 1, DecodeError::MissingField, "protocol_version", "absent (0)") ||
        !c.require(m.species.size() <= std::size_t(kMaxSpecies), DecodeError::BadLength, "species",
                   count(m.species.size()) + " entries, at most 255"))
        return c.result();
    for (const SpeciesInfo& s : m.species) {
        if (!checkName(c, s.name, "species.name") ||
            !c.require(std::uint8_t(s.kind) <= std::uint8_t(SpeciesKind::Volume), DecodeError::Unsupported,
                       "species.kind", "unknown kind " + std::to_string(int(s.kind))))
            return c.result();
    }
    const auto& d = m.gridDims;
    const bool noMap = d[0] == 0 && d[1] == 0 && d[2] == 0;
    const bool dimsOk = std::all_of(d.begin(), d.end(), [](std::int32_t n) { return n > 0 && n <= kMaxGridDim; });
    checkBox(c, m.boxLo, m.boxHi, "box") && c.finite(m.gridOriginMm, "grid_origin_mm") &&
        c.require(noMap || dimsOk, DecodeError::OutOfRange, "grid_dims", "all 0, or all in 1..65536") &&
        c.finite(m.voxelSizeMm, "voxel_size_mm") &&
        c.require(noMap || m.voxelSizeMm > 0, DecodeError::OutOfRange, "voxel_size_mm", "not > 0") &&
        c.finite(m.r0, "r0") && c.require(m.r0 > 0, DecodeError::OutOfRange, "r0", "not > 0") &&
        c.finite(m.r0Voxels, "r0_voxels") &&
        c.require(m.r0Voxels >= 0, DecodeError::OutOfRange, "r0_voxels", "negative") && c.finite(m.dt, "dt") &&
        c.require(m.dt > 0, DecodeError::OutOfRange, "dt", "not > 0") && c.finite(m.publishRateHz, "publish_rate_hz") &&
        c.require(m.publishRateHz >= 0 && m.publishRateHz <= kMaxFrameRateHz, DecodeError::OutOfRange,
                  "publish_rate_hz", "outside 0.." + std::to_string(int(kMaxFrameRateHz)) + " Hz") &&
        c.finite(m.probeReach, "probe_reach") && validTunables(c, m.tunables, m.species.size()) &&
        c.require(m.probeReach >= 0, DecodeError::OutOfRange, "probe_reach", "negative") &&
        c.within(m.sessionTimeoutS, 0, 1e6, "session_timeout_s") &&
        c.within(m.unitSystem.lengthMm, 0, 1e9, "length_mm") && c.within(m.unitSystem.massKg, 0, 1e9, "mass_kg") &&
        c.within(m.unitSystem.timeS, 0, 1e9, "time_s") &&
        c.require(
            !m.unitSystem.physical || (m.unitSystem.lengthMm > 0 && m.unitSystem.massKg > 0 &&
                                       m.unitSystem.massKg < 1e9 && m.unitSystem.timeS > 0 && m.unitSystem.timeS < 1e9),
            DecodeError::OutOfRange, "physical_units", "length_mm, mass_kg and time_s not all in (0, 1e9)") &&
        c.maxBytes(m.endpoints.frameEndpoint, kMaxEndpointBytes, "endpoints.frame_endpoint") &&
        c.maxBytes(m.units, kMaxTextBytes, "units");
    return c.result();
}

Validation validate(const Probe& m) {
    using namespace ranges;
    Checker c("Probe");
    c.within(m.position, kMaxCoordinate, "position") && c.within(m.k0, kMinProbeK0, kMaxProbeK0, "k0") &&
        c.within(m.k1, kMinProbeK1, kMaxProbeK1, "k1") && validLoop(c, m.loop, "loop") &&
        c.within(m.renderedForce, kMaxRenderedForce, "rendered_force");
    return c.result();
}

Validation validate(const MapRequest& m) {
    Checker c("MapRequest");
    c.require(m.length >= 1 && m.length <= kMaxMapPieceBytes, DecodeError::OutOfRange, "length",
              std::to_string(m.length) + " bytes, expected 1.." + std::to_string(kMaxMapPieceBytes));
    return c.result();
}

Validation validate(const MapChunk& m) {
    Checker c("MapChunk");
    c.require(m.data.size() <= kMaxMapPieceBytes, DecodeError::BadLength, "data",
              std::to_string(m.data.size()) + " bytes, at most " + std::to_string(kMaxMapPieceBytes)) &&
        c.require(m.offset <= m.total && m.data.size() <= m.total - m.offset, DecodeError::OutOfRange, "offset",
                  "the piece [" + std::to_string(m.offset) + ", +" + std::to_string(m.data.size()) +
                      ") is not within the file's " + std::to_string(m.total) + " bytes");
    return c.result();
}

Validation validate(const MapEditsRequest&) {
    return {};  // any number: the server answers from the nearest it has
}

Validation validate(const MapEdits& m) {
    Checker c("MapEdits");
    const std::uint64_t end = std::uint64_t(m.first) + m.edits.size();
    if (!(c.require(m.edits.size() <= kMaxEditsPerMessage, DecodeError::BadLength, "edits",
                    std::to_string(m.edits.size()) + " edits, at most " + std::to_string(kMaxEditsPerMessage)) &&
          c.require(end <= m.total, DecodeError::OutOfRange, "first",
                    "edits " + std::to_string(m.first) + ".." + std::to_string(end) + " beyond total " +
                        std::to_string(m.total))))
        return c.result();
    std::size_t bytes = 0;
    for (const MapEdit& e : m.edits) bytes += mapEditWireBytes(e.voxels.size());
    if (!c.require(
            bytes <= kMaxMapEditsPayload, DecodeError::TooLarge, "edits",
            "about " + std::to_string(bytes) + " bytes of edits, at most " + std::to_string(kMaxMapEditsPayload)))
        return c.result();
    for (const MapEdit& e : m.edits) {
        const bool blade = e.cut.radius > 0;
        bool ok =
            c.within(e.cut.from, ranges::kMaxCoordinate, "edits.from") &&
            c.within(e.cut.to, ranges::kMaxCoordinate, "edits.to") &&
            c.within(e.cut.radius, 0, ranges::kMaxCoordinate, "edits.radius") &&
            c.require(
                blade ? e.voxels.empty() : !e.voxels.empty() && e.voxels.size() <= kMaxEditVoxels,
                DecodeError::BadLength, "edits.voxels",
                std::to_string(e.voxels.size()) + (blade ? " voxels with a blade, expected none"
                                                         : " voxels, expected 1.." + std::to_string(kMaxEditVoxels))) &&
            c.require(std::adjacent_find(e.voxels.begin(), e.voxels.end(), std::greater_equal<>()) == e.voxels.end(),
                      DecodeError::OutOfRange, "edits.voxels", "not increasing");
        if (!ok) break;
    }
    return c.result();
}

Validation validate(const Refusal& m) {
    Checker c("Refusal");
    c.maxBytes(m.kind, kMaxNameBytes, "kind") && c.maxBytes(m.reason, kMaxTextBytes, "reason");
    return c.result();
}

Validation validate(const Feedback& m) {
    Checker c("Feedback");
    c.finite(m.force, "force");
    return c.result();
}

Validation validate(const Command& m) {
    Checker c("Command");
    std::visit([&c](const auto& body) { checkBody(c, body); }, m.body);
    return c.result();
}

Validation validate(const CommandReply& m) {
    Checker c("CommandReply");
    c.require(std::uint8_t(m.status) <= std::uint8_t(ReplyStatus::Failed), DecodeError::Unsupported, "status",
              "unknown status " + std::to_string(int(m.status))) &&
        c.maxBytes(m.message, kMaxTextBytes, "message");
    return c.result();
}

Validation validate(const StateFrame& m, const FrameLimits& limits) {
    Checker c("StateFrame");
    const std::size_t n = m.count();
    const int maxSpecies = limits.speciesCount > 0 ? std::min(limits.speciesCount, kMaxSpecies) : kMaxSpecies;
    const bool lengthsOk =
        c.require(m.chunkCount >= 1 && m.chunkCount <= limits.maxChunkCount, DecodeError::OutOfRange, "chunk_count",
                  std::to_string(m.chunkCount) + ", expected 1.." + std::to_string(limits.maxChunkCount)) &&
        c.require(m.chunkIndex < m.chunkCount, DecodeError::OutOfRange, "chunk_index",
                  std::to_string(m.chunkIndex) + " not below chunk_count " + std::to_string(m.chunkCount)) &&
        c.require(std::uint64_t(m.firstIndex) + n <= m.frameParticleCount, DecodeError::OutOfRange, "first_index",
                  "particles " + std::to_string(m.firstIndex) + ".." + count(m.firstIndex + n) +
                      " beyond frame_particle_count " + std::to_string(m.frameParticleCount)) &&
        c.require(m.positions.size() == 3 * n, DecodeError::BadLength, "positions",
                  count(m.positions.size()) + " values, expected 3 x " + count(n)) &&
        c.require(m.normals.empty() || m.normals.size() == 3 * n, DecodeError::BadLength, "normals",
                  count(m.normals.size()) + " values, expected 0 or 3 x " + count(n)) &&
        c.require(m.ids.empty() || m.ids.size() == n, DecodeError::BadLength, "ids",
                  count(m.ids.size()) + " values, expected 0 or " + count(n));
    if (!lengthsOk) return c.result();
    const bool quantised = m.encoding == FrameEncoding::Quantised16 || m.encoding == FrameEncoding::Compact8;
    const bool headerOk =
        c.require(quantised || m.encoding == FrameEncoding::Float32, DecodeError::Unsupported, "encoding",
                  "unknown encoding " + std::to_string(int(m.encoding))) &&
        (!quantised || checkQuantBounds(c, m.quantLo, m.quantHi)) && c.finite(m.simTime, "sim_time") &&
        c.finite(m.probePosition, "probe_position") && c.finite(m.probeForce, "probe_force") &&
        c.finite(m.stats.kinetic, "stats.kinetic_energy") && c.finite(m.stats.potential, "stats.potential_energy") &&
        c.finite(m.stats.pressure, "stats.pressure") && c.finite(m.stats.stepRateHz, "stats.step_rate_hz") &&
        c.finite(m.stats.cavityVolume, "stats.cavity_volume") && c.finite(m.stats.mapFrame, "stats.map_frame") &&
        validLoop(c, m.stats.haptic, "stats.haptic");
    if (!headerOk) return c.result();
    c.speciesArray(m.species.data(), n, 1, maxSpecies, "species") &&
        c.finiteArray(m.positions.data(), m.positions.size(), "positions") &&
        c.finiteArray(m.normals.data(), m.normals.size(), "normals");
    return c.result();
}

}  // namespace bop::protocol
