#include "HostileMessages.hpp"

#include "codec/Ranges.hpp"
#include "command_generated.h"
#include "hello_generated.h"
#include "map_request_generated.h"
#include "probe_generated.h"
#include "server/InboundRanges.hpp"

namespace bop::test::hostile {
namespace {

using namespace bop::protocol;

Buffer finished(flatbuffers::FlatBufferBuilder& fbb) {
    return Buffer(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

}  // namespace

Buffer probeMessage(const Eigen::Vector3d& x, double k0, double k1, float rateHz, float p99Us,
                    const Eigen::Vector3d& rendered, std::uint64_t seq) {
    flatbuffers::FlatBufferBuilder fbb;
    const bop::wire::Vec3 at(x.x(), x.y(), x.z()), f(rendered.x(), rendered.y(), rendered.z());
    const bop::wire::LoopStats loop(rateHz, p99Us, 0);
    bop::wire::FinishProbeBuffer(fbb, bop::wire::CreateProbe(fbb, seq, 0, &at, true, k0, k1, &loop, &f));
    return finished(fbb);
}
Buffer helloMessage(float rateHz) {
    flatbuffers::FlatBufferBuilder fbb;
    bop::wire::FinishHelloBuffer(fbb, bop::wire::CreateHello(fbb, 1, bop::wire::Role::Haptic, rateHz));
    return finished(fbb);
}
Buffer commandMessage(flatbuffers::FlatBufferBuilder& fbb, bop::wire::CommandBody type,
                      flatbuffers::Offset<void> body) {
    bop::wire::FinishCommandBuffer(fbb, bop::wire::CreateCommand(fbb, 77, type, body));
    return finished(fbb);
}
Buffer seedMessage(int species, const Eigen::Vector3d& x) {
    flatbuffers::FlatBufferBuilder fbb;
    const bop::wire::Vec3 at(x.x(), x.y(), x.z());
    return commandMessage(fbb, bop::wire::CommandBody::SeedParticle,
                          bop::wire::CreateSeedParticle(fbb, std::uint8_t(species), &at).Union());
}
Buffer birthMessage(int species) {
    flatbuffers::FlatBufferBuilder fbb;
    return commandMessage(fbb, bop::wire::CommandBody::SetBirth,
                          bop::wire::CreateSetBirth(fbb, std::uint8_t(species)).Union());
}
Buffer parameterMessage(const char* name, double value, int a, int b) {
    flatbuffers::FlatBufferBuilder fbb;
    return commandMessage(
        fbb, bop::wire::CommandBody::SetParameter,
        bop::wire::CreateSetParameterDirect(fbb, name, std::uint8_t(a), std::uint8_t(b), value).Union());
}
Buffer singleStepMessage(std::uint32_t steps) {
    flatbuffers::FlatBufferBuilder fbb;
    return commandMessage(fbb, bop::wire::CommandBody::RunControl,
                          bop::wire::CreateRunControl(fbb, bop::wire::RunAction::SingleStep, steps).Union());
}
Buffer mapRequestMessage(std::uint64_t offset, std::uint32_t length) {
    flatbuffers::FlatBufferBuilder fbb;
    fbb.ForceDefaults(true);
    bop::wire::FinishMapRequestBuffer(fbb, bop::wire::CreateMapRequest(fbb, offset, length));
    return finished(fbb);
}

std::vector<Case> outOfRange(const SceneInfo& scene) {
    using namespace ranges;
    const Eigen::Vector3d c = 0.5 * (scene.boxLo + scene.boxHi), reach = probeReachBox(scene).max();
    const int beyond = int(scene.species.size()) + 1;  // a species number the scene does not have
    const double above = 1 + 1e-6;
    std::vector<Case> v = {
        {"probe k0 just below", probeMessage(c, kMinProbeK0 * (1 - 1e-6)), "Probe.k0"},
        {"probe k0 just above", probeMessage(c, kMaxProbeK0 * above), "Probe.k0"},
        {"probe k0 NaN", probeMessage(c, kNaN), "Probe.k0"},
        {"probe k0 infinite", probeMessage(c, kInf), "Probe.k0"},
        {"probe k0 huge", probeMessage(c, 1e300), "Probe.k0"},
        {"probe k1 just below", probeMessage(c, 1, -1e-9), "Probe.k1"},
        {"probe k1 just above", probeMessage(c, 1, kMaxProbeK1 * above), "Probe.k1"},
        {"probe k1 NaN", probeMessage(c, 1, kNaN), "Probe.k1"},
        {"probe k1 infinite", probeMessage(c, 1, -kInf), "Probe.k1"},
        {"probe k1 huge", probeMessage(c, 1, 1e300), "Probe.k1"},
        {"probe beyond the box's reach", probeMessage(reach + Eigen::Vector3d(0, 0, 0.01)), "Probe.position"},
        {"probe beyond any coordinate", probeMessage({kMaxCoordinate * above, 5, 5}), "Probe.position"},
        {"probe position NaN", probeMessage({5, kNaN, 5}), "Probe.position"},
        {"probe position infinite", probeMessage({5, 5, kInf}), "Probe.position"},
        {"probe position huge", probeMessage({-1e300, 5, 5}), "Probe.position"},
        {"loop rate negative", probeMessage(c, 1, 1, -1), "Probe.loop"},
        {"loop rate just above", probeMessage(c, 1, 1, kMaxLoopRateHz * 1.001f), "Probe.loop"},
        {"loop rate NaN", probeMessage(c, 1, 1, float(kNaN)), "Probe.loop"},
        {"loop error infinite", probeMessage(c, 1, 1, 1000, float(kInf)), "Probe.loop"},
        {"loop error just above", probeMessage(c, 1, 1, 1000, kMaxPeriodErrorUs * 1.001f), "Probe.loop"},
        {"rendered force just above", probeMessage(c, 1, 1, 0, 0, {0, kMaxRenderedForce * above, 0}),
         "Probe.rendered_force"},
        {"rendered force NaN", probeMessage(c, 1, 1, 0, 0, {kNaN, 0, 0}), "Probe.rendered_force"},
        {"rendered force huge", probeMessage(c, 1, 1, 0, 0, {0, 0, 1e300}), "Probe.rendered_force"},
        {"seed outside the box", seedMessage(1, {c.x(), c.y(), scene.boxHi.z() + 1e-3}), "SeedParticle.position"},
        {"seed position NaN", seedMessage(1, {kNaN, c.y(), c.z()}), "SeedParticle.position"},
        {"seed position huge", seedMessage(1, {c.x(), 1e300, c.z()}), "SeedParticle.position"},
        {"seed species 0", seedMessage(0, c), "SeedParticle.species"},
        {"seed species beyond the scene's", seedMessage(beyond, c), "SeedParticle.species"},
        {"birth species beyond the scene's", birthMessage(beyond), "SetBirth.species"},
        {"single steps 0", singleStepMessage(0), "RunControl.steps"},
        {"single steps just above", singleStepMessage(kMaxSingleSteps + 1), "RunControl.steps"},
        {"map request of 0 bytes", mapRequestMessage(0, 0), "MapRequest.length"},
        {"map request just above 1 MiB", mapRequestMessage(0, std::uint32_t(kMaxMapPieceBytes + 1)),
         "MapRequest.length"},
        {"map request beyond the file", mapRequestMessage(scene.mapBytes + 1, 10), "MapRequest.offset"},
        {"weight of species 0", parameterMessage("lj", 1, 0, 1), "SetParameter.species_a"},
        {"weight of species beyond the scene's", parameterMessage("co_planar", 1, 1, beyond), "SetParameter.species_b"},
        {"drag of species beyond the scene's", parameterMessage("drag_w", 1, beyond, 0), "SetParameter.species_a"},
    };
    const std::pair<const char*, std::pair<double, double>> bounded[] = {
        {"lj", {0, kMaxWeight}},
        {"co_normal", {0, kMaxWeight}},
        {"co_planar", {0, kMaxWeight}},
        {"drag_v", {0, kMaxDrag}},
        {"drag_w", {0, kMaxDrag}},
        {"k0", {kMinProbeK0, kMaxProbeK0}},
        {"k1", {kMinProbeK1, kMaxProbeK1}},
    };
    for (const auto& [name, range] : bounded)
        for (const double x : {range.first - 1e-9, range.second * above, kNaN, kInf, 1e300})
            v.push_back({name, parameterMessage(name, x), "SetParameter.value"});
    return v;
}

}  // namespace bop::test::hostile
