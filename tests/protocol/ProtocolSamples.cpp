// Sample messages and comparisons for the protocol tests; see ProtocolSamples.hpp.
#include "ProtocolSamples.hpp"

#include <random>
#include <string>
#include <variant>

namespace bop::protocol::samples {

namespace {

bool eq(const SeedParticle& a, const SeedParticle& b) {
    return a.species == b.species && a.position == b.position;
}
bool eq(const SetBirth& a, const SetBirth& b) {
    return a.species == b.species && a.enabled == b.enabled;
}
bool eq(const SetParameter& a, const SetParameter& b) {
    return a.name == b.name && a.speciesA == b.speciesA && a.speciesB == b.speciesB && a.value == b.value;
}
bool eq(const RunControl& a, const RunControl& b) {
    return a.action == b.action && a.steps == b.steps;
}
bool eq(const SwitchMapFrame& a, const SwitchMapFrame& b) {
    return a.frame == b.frame;
}
bool eq(const Checkpoint& a, const Checkpoint& b) {
    return a.path == b.path;
}
bool eq(const Record& a, const Record& b) {
    return a.start == b.start && a.path == b.path;
}
bool eq(const Cut& a, const Cut& b) {
    return a.from == b.from && a.to == b.to && a.radius == b.radius;
}

template <class T, class Decode>
DecodeCheck roundAgain(Decoded<T> d, Buffer (*encode)(const T&), Decode decode) {
    DecodeCheck out;
    out.error = d.error;
    if (!d.ok()) return out;
    const Buffer again = encode(d.value);  // throws EncodeError if the decoder let a bad value through
    const Decoded<T> d2 = decode(again.data(), again.size());
    out.stable = d2.ok() && same(d.value, d2.value);
    return out;
}

}  // namespace

Hello sampleHello() {
    Hello h;
    h.role = Role::Haptic;
    h.frameRateHz = 60;
    h.readOnly = true;
    h.clientName = "bop-haptic test";
    h.udpFramePort = 40123;
    return h;
}

SceneInfo sampleScene(int speciesCount) {
    SceneInfo s;
    for (int k = 1; k <= speciesCount; ++k) {
        const auto c = std::uint8_t(40 * k);
        s.species.push_back({"species " + std::to_string(k),
                             k % 2 ? SpeciesKind::Surface : SpeciesKind::Volume,
                             {c, std::uint8_t(255 - c), 128, 255}});
    }
    s.boxLo = {-10, 0, -3};
    s.boxHi = {20, 5, 3};
    s.gridOriginMm = {-1.5, 2.25, 0};
    s.gridDims = {64, 48, 32};
    s.voxelSizeMm = 0.5;
    s.r0Voxels = 1.4;
    s.dt = 0.005;
    s.endpoints = {"tcp://127.0.0.1:7701", 7702, 7703};
    s.particleCount = 123456;
    s.publishRateHz = 60;
    s.probeReach = 2.77;
    s.mapBytes = 123456789;
    s.mapKey = 0xfeedface12345678ull;
    s.sessionTimeoutS = 30;
    s.unitSystem = bop::UnitSystem::fromModulus(1.155, 5.66e-6, 5e3, 0.5);
    if (std::size_t(speciesCount) <= kMaxTunedSpecies) {
        const std::size_t n = std::size_t(speciesCount);
        for (std::size_t k = 0; k < n * n; ++k)
            s.tunables.lj.push_back(1 + 0.1 * double(k)), s.tunables.coNormal.push_back(0.3),
                s.tunables.coPlanar.push_back(0.2 * double(k));
        for (std::size_t k = 0; k < n; ++k)
            s.tunables.dragV.push_back(1.5), s.tunables.dragW.push_back(0.25 * double(k));
        s.tunables.k0 = 1.25;
        s.tunables.k1 = 3;
    }
    s.units = "length: r0 = sqrt(3); time: simulation units; force: simulation units";
    return s;
}

Probe sampleProbe() {
    return {42, 1'234'567'890'123, {1.25, -2.5, 0.75}, true, 1.5, 0.25, {999.5f, 12.25f, 3}, {0.5, -1.25, 2}};
}

MapRequest sampleMapRequest() {
    return {1 << 20, 65536};
}

MapChunk sampleMapChunk() {
    MapChunk m{4096, 10000, {}};
    for (int k = 0; k < 300; ++k) m.data.push_back(std::uint8_t(7 * k));
    return m;
}

MapEditsRequest sampleMapEditsRequest() {
    return {17};
}

MapEdits sampleMapEdits() {
    MapEdits m{5, 9, {}};
    m.edits.push_back({Cut{{1.5, -2, 0.25}, {3, 4.5, -1}, 0.75}, {}});
    m.edits.push_back({Cut{}, {3, 7, 8, 4096, 70000}});
    return m;
}

Refusal sampleRefusal() {
    return {"Probe", 77, "Probe.k1: 1e+300 outside 0..50", 3};
}

Feedback sampleFeedback() {
    return {41, 9001, {-0.125, 3.5, 1e-3}, 9'876'543'210, 12};
}

std::vector<Command> sampleCommands() {
    return {{1, SeedParticle{3, {1, 2, 3}}},
            {2, SetBirth{2, false}},
            {3, SetParameter{"lj", 1, 2, 0.75}},
            {4, RunControl{RunAction::SingleStep, 5}},
            {5, SwitchMapFrame{7}},
            {6, Checkpoint{"out/checkpoint.xyz"}},
            {7, Record{true, "out/session.bop"}},
            {8, Cut{{1, 2, 3}, {4, 5, 6}, 1.5}}};
}

CommandReply sampleReply() {
    return {6, ReplyStatus::Failed, 1200, "could not write out/checkpoint.xyz"};
}

StateFrame sampleFrame(std::size_t n, FrameEncoding encoding, bool withNormals, bool withIds, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    StateFrame f;
    f.frameSeq = 17;
    f.step = 3400;
    f.simTime = 17.0;
    f.serverTimeNs = 5'000'000'123;
    f.probePosition = {0.5, 1.0, -0.25};
    f.probeForce = {0.0, -2.0, 0.125};
    f.probeActive = true;
    f.stats = {12.5, -340.25, 0.0625, 480.0, n, {1000.25f, 8.5f, 2}, 93.5, 2.25, 0.75};
    f.frameParticleCount = std::uint32_t(n);
    f.encoding = encoding;
    f.quantLo = {-10, 0, -3};
    f.quantHi = {20, 5, 3};
    for (std::size_t i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) f.positions.push_back(float(f.quantLo[a] + u(rng) * (f.quantHi[a] - f.quantLo[a])));
        const Eigen::Vector3d nrm = Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        if (withNormals)
            for (int a = 0; a < 3; ++a) f.normals.push_back(float(nrm[a]));
        f.species.push_back(std::uint8_t(1 + i % 4));
        if (withIds) f.ids.push_back((std::uint64_t(i) << 32) | (i * 7919));
    }
    return f;
}

bool same(const Hello& a, const Hello& b) {
    return a.protocolVersion == b.protocolVersion && a.role == b.role && a.frameRateHz == b.frameRateHz &&
           a.readOnly == b.readOnly && a.clientName == b.clientName && a.udpFramePort == b.udpFramePort;
}

bool same(const SceneInfo& a, const SceneInfo& b) {
    if (a.species.size() != b.species.size()) return false;
    for (std::size_t i = 0; i < a.species.size(); ++i)
        if (a.species[i].name != b.species[i].name || a.species[i].kind != b.species[i].kind ||
            a.species[i].rgba != b.species[i].rgba)
            return false;
    return a.protocolVersion == b.protocolVersion && a.boxLo == b.boxLo && a.boxHi == b.boxHi &&
           a.gridOriginMm == b.gridOriginMm && a.gridDims == b.gridDims && a.voxelSizeMm == b.voxelSizeMm &&
           a.r0 == b.r0 && a.r0Voxels == b.r0Voxels && a.dt == b.dt &&
           a.endpoints.frameEndpoint == b.endpoints.frameEndpoint &&
           a.endpoints.udpFramePort == b.endpoints.udpFramePort &&
           a.endpoints.udpProbePort == b.endpoints.udpProbePort && a.particleCount == b.particleCount &&
           a.units == b.units && a.publishRateHz == b.publishRateHz && a.probeReach == b.probeReach &&
           a.mapBytes == b.mapBytes && a.mapKey == b.mapKey && a.sessionTimeoutS == b.sessionTimeoutS &&
           a.unitSystem.lengthMm == b.unitSystem.lengthMm && a.unitSystem.massKg == b.unitSystem.massKg &&
           a.unitSystem.timeS == b.unitSystem.timeS && a.unitSystem.physical == b.unitSystem.physical &&
           a.tunables.lj == b.tunables.lj && a.tunables.coNormal == b.tunables.coNormal &&
           a.tunables.coPlanar == b.tunables.coPlanar && a.tunables.dragV == b.tunables.dragV &&
           a.tunables.dragW == b.tunables.dragW && a.tunables.k0 == b.tunables.k0 && a.tunables.k1 == b.tunables.k1;
}

bool same(const Probe& a, const Probe& b) {
    return a.seq == b.seq && a.clientTimeNs == b.clientTimeNs && a.position == b.position && a.active == b.active &&
           a.k0 == b.k0 && a.k1 == b.k1 && same(a.loop, b.loop) && a.renderedForce == b.renderedForce;
}

bool same(const LoopStats& a, const LoopStats& b) {
    return a.rateHz == b.rateHz && a.periodErrorP99Us == b.periodErrorP99Us && a.missedDeadlines == b.missedDeadlines;
}

bool same(const MapRequest& a, const MapRequest& b) {
    return a.offset == b.offset && a.length == b.length;
}

bool same(const MapChunk& a, const MapChunk& b) {
    return a.offset == b.offset && a.total == b.total && a.data == b.data;
}

bool same(const MapEditsRequest& a, const MapEditsRequest& b) {
    return a.first == b.first;
}

bool same(const MapEdits& a, const MapEdits& b) {
    const auto edit = [](const MapEdit& x, const MapEdit& y) {
        return x.cut.from == y.cut.from && x.cut.to == y.cut.to && x.cut.radius == y.cut.radius && x.voxels == y.voxels;
    };
    return a.first == b.first && a.total == b.total &&
           std::equal(a.edits.begin(), a.edits.end(), b.edits.begin(), b.edits.end(), edit);
}

bool same(const Refusal& a, const Refusal& b) {
    return a.kind == b.kind && a.seq == b.seq && a.reason == b.reason && a.refused == b.refused;
}

bool same(const Feedback& a, const Feedback& b) {
    return a.probeSeq == b.probeSeq && a.step == b.step && a.force == b.force && a.serverTimeNs == b.serverTimeNs &&
           a.mapEdits == b.mapEdits;
}

bool same(const Command& a, const Command& b) {
    if (a.requestId != b.requestId || a.body.index() != b.body.index()) return false;
    return std::visit([&b](const auto& x) { return eq(x, std::get<std::decay_t<decltype(x)>>(b.body)); }, a.body);
}

bool same(const CommandReply& a, const CommandReply& b) {
    return a.requestId == b.requestId && a.status == b.status && a.step == b.step && a.message == b.message;
}

bool same(const StateFrame& a, const StateFrame& b) {
    const bool quantised = a.encoding != FrameEncoding::Float32;
    return a.frameSeq == b.frameSeq && a.chunkIndex == b.chunkIndex && a.chunkCount == b.chunkCount &&
           a.step == b.step && a.simTime == b.simTime && a.serverTimeNs == b.serverTimeNs &&
           a.probePosition == b.probePosition && a.probeForce == b.probeForce && a.probeActive == b.probeActive &&
           a.stats.kinetic == b.stats.kinetic && a.stats.potential == b.stats.potential &&
           a.stats.pressure == b.stats.pressure && a.stats.stepRateHz == b.stats.stepRateHz &&
           a.stats.particleCount == b.stats.particleCount && same(a.stats.haptic, b.stats.haptic) &&
           a.stats.cavityVolume == b.stats.cavityVolume && a.stats.mapFrame == b.stats.mapFrame &&
           a.stats.realTimeFactor == b.stats.realTimeFactor && a.frameParticleCount == b.frameParticleCount &&
           a.firstIndex == b.firstIndex && a.encoding == b.encoding &&
           (!quantised || (a.quantLo == b.quantLo && a.quantHi == b.quantHi)) && a.positions == b.positions &&
           a.normals == b.normals && a.species == b.species && a.ids == b.ids;
}

std::vector<Sample> allSamples() {
    std::vector<Sample> out{{MessageKind::Hello, encodeHello(sampleHello())},
                            {MessageKind::SceneInfo, encodeSceneInfo(sampleScene())},
                            {MessageKind::Probe, encodeProbe(sampleProbe())},
                            {MessageKind::Feedback, encodeFeedback(sampleFeedback())},
                            {MessageKind::CommandReply, encodeCommandReply(sampleReply())},
                            {MessageKind::MapRequest, encodeMapRequest(sampleMapRequest())},
                            {MessageKind::MapChunk, encodeMapChunk(sampleMapChunk())},
                            {MessageKind::MapEditsRequest, encodeMapEditsRequest(sampleMapEditsRequest())},
                            {MessageKind::MapEdits, encodeMapEdits(sampleMapEdits())},
                            {MessageKind::Refusal, encodeRefusal(sampleRefusal())}};
    for (const Command& c : sampleCommands()) out.push_back({MessageKind::Command, encodeCommand(c)});
    out.push_back({MessageKind::StateFrame, encodeStateFrame(sampleFrame(5, FrameEncoding::Float32, true, true))});
    out.push_back({MessageKind::StateFrame, encodeStateFrame(sampleFrame(5, FrameEncoding::Quantised16, true, false))});
    out.push_back({MessageKind::StateFrame, encodeStateFrame(sampleFrame(6, FrameEncoding::Compact8, true, true))});
    return out;
}

DecodeCheck decodeAs(MessageKind kind, const std::uint8_t* buf, std::size_t len) {
    switch (kind) {
        case MessageKind::Hello:
            return roundAgain(decodeHello(buf, len), &encodeHello, &decodeHello);
        case MessageKind::SceneInfo:
            return roundAgain(decodeSceneInfo(buf, len), &encodeSceneInfo, &decodeSceneInfo);
        case MessageKind::Probe:
            return roundAgain(decodeProbe(buf, len), &encodeProbe, &decodeProbe);
        case MessageKind::Feedback:
            return roundAgain(decodeFeedback(buf, len), &encodeFeedback, &decodeFeedback);
        case MessageKind::Command:
            return roundAgain(decodeCommand(buf, len), &encodeCommand, &decodeCommand);
        case MessageKind::CommandReply:
            return roundAgain(decodeCommandReply(buf, len), &encodeCommandReply, &decodeCommandReply);
        case MessageKind::MapRequest:
            return roundAgain(decodeMapRequest(buf, len), &encodeMapRequest, &decodeMapRequest);
        case MessageKind::MapChunk:
            return roundAgain(decodeMapChunk(buf, len), &encodeMapChunk, &decodeMapChunk);
        case MessageKind::MapEditsRequest:
            return roundAgain(decodeMapEditsRequest(buf, len), &encodeMapEditsRequest, &decodeMapEditsRequest);
        case MessageKind::MapEdits:
            return roundAgain(decodeMapEdits(buf, len), &encodeMapEdits, &decodeMapEdits);
        case MessageKind::Refusal:
            return roundAgain(decodeRefusal(buf, len), &encodeRefusal, &decodeRefusal);
        case MessageKind::StateFrame: {
            FrameLimits limits;
            limits.speciesCount = 4;
            const auto decode = [limits](const std::uint8_t* p, std::size_t n) {
                return decodeStateFrame(p, n, limits);
            };
            return roundAgain(decode(buf, len), &encodeStateFrame, decode);
        }
        case MessageKind::Unknown:
            break;
    }
    return {DecodeError::Unsupported, false};
}

bool decodesToSameAs(MessageKind kind, const std::uint8_t* buf, std::size_t len, const Buffer& original) {
    const DecodeCheck a = decodeAs(kind, buf, len);
    if (a.error != DecodeError::None || !a.stable) return false;
    // Same value as the original: compare the re-encoded bytes of both decodes.
    const auto reencode = [kind](const std::uint8_t* p, std::size_t n) -> Buffer {
        switch (kind) {
            case MessageKind::Hello:
                return encodeHello(decodeHello(p, n).value);
            case MessageKind::SceneInfo:
                return encodeSceneInfo(decodeSceneInfo(p, n).value);
            case MessageKind::Probe:
                return encodeProbe(decodeProbe(p, n).value);
            case MessageKind::Feedback:
                return encodeFeedback(decodeFeedback(p, n).value);
            case MessageKind::Command:
                return encodeCommand(decodeCommand(p, n).value);
            case MessageKind::CommandReply:
                return encodeCommandReply(decodeCommandReply(p, n).value);
            case MessageKind::MapRequest:
                return encodeMapRequest(decodeMapRequest(p, n).value);
            case MessageKind::MapChunk:
                return encodeMapChunk(decodeMapChunk(p, n).value);
            case MessageKind::MapEditsRequest:
                return encodeMapEditsRequest(decodeMapEditsRequest(p, n).value);
            case MessageKind::MapEdits:
                return encodeMapEdits(decodeMapEdits(p, n).value);
            case MessageKind::Refusal:
                return encodeRefusal(decodeRefusal(p, n).value);
            case MessageKind::StateFrame:
                return encodeStateFrame(decodeStateFrame(p, n).value);
            case MessageKind::Unknown:
                break;
        }
        return {};
    };
    return reencode(buf, len) == reencode(original.data(), original.size());
}

}  // namespace bop::protocol::samples
