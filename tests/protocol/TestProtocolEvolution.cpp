// Schema evolution: buffers written with draft 0 of the probe and frame schemas
// (old_schemas/*_v0.fbs, generated for this test) read with today's decoders, and today's
// buffers read with the draft-0 generated code. Fields are only appended, so each side reads
// what it knows and the new fields take their schema defaults.
#include "ProtocolSamples.hpp"
#include "frame_v0_generated.h"
#include "probe_v0_generated.h"

#include <catch2/catch.hpp>

using namespace bop::protocol;
using namespace bop::protocol::samples;
namespace v0 = bop::wire::v0;

namespace {

Buffer finish(const flatbuffers::FlatBufferBuilder& fbb) {
    return Buffer(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

}  // namespace

TEST_CASE("a draft-0 probe reads with k0 and k1 at their defaults", "[protocol]") {
    flatbuffers::FlatBufferBuilder fbb;
    const v0::Vec3 at(0.5, -1.5, 2.0);
    v0::FinishProbeBuffer(fbb, v0::CreateProbe(fbb, 77, 123456789, &at, true));
    const Buffer old = finish(fbb);
    const Decoded<Probe> p = decodeProbe(old.data(), old.size());
    REQUIRE(p.ok());
    CHECK(p.value.seq == 77);
    CHECK(p.value.clientTimeNs == 123456789);
    CHECK(p.value.position == Eigen::Vector3d(0.5, -1.5, 2.0));
    CHECK(p.value.active);
    CHECK(p.value.k0 == 1.0);  // schema defaults of the appended fields
    CHECK(p.value.k1 == 1.0);
    CHECK(old.size() < encodeProbe(p.value).size());  // the old buffer really lacks the new fields
}

TEST_CASE("a draft-0 reader reads today's probe", "[protocol]") {
    const Buffer now = encodeProbe(sampleProbe());
    flatbuffers::Verifier verifier(now.data(), now.size());
    REQUIRE(v0::VerifyProbeBuffer(verifier));
    const v0::Probe* old = v0::GetProbe(now.data());
    CHECK(old->seq() == sampleProbe().seq);
    CHECK(old->client_time_ns() == sampleProbe().clientTimeNs);
    CHECK(old->position()->x() == sampleProbe().position.x());
    CHECK(old->position()->z() == sampleProbe().position.z());
    CHECK(old->active() == sampleProbe().active);
}

TEST_CASE("a draft-0 frame reads as a float32 frame without ids", "[protocol]") {
    flatbuffers::FlatBufferBuilder fbb;
    const std::vector<float> positions{1, 2, 3, 4, 5, 6}, normals{0, 0, 1, 1, 0, 0};
    const std::vector<std::uint8_t> species{1, 2};
    const auto stats = v0::CreateFrameStats(fbb, 1.5, -2.5, 0.25, 100.0, 2);
    const v0::Vec3 probe(0.25, 0.5, 0.75), force(-1, 0, 1);
    v0::FinishStateFrameBuffer(fbb, v0::CreateStateFrameDirect(fbb, 9, 0, 1, 400, 2.0, 555, &probe, &force, true, stats,
                                                               2, 0, &positions, &normals, &species));
    const Buffer old = finish(fbb);
    const Decoded<StateFrame> f = decodeStateFrame(old.data(), old.size());
    REQUIRE(f.ok());
    CHECK(f.value.encoding == FrameEncoding::Float32);
    CHECK(f.value.ids.empty());
    CHECK(f.value.positions == positions);
    CHECK(f.value.normals == normals);
    CHECK(f.value.species == species);
    CHECK(f.value.frameSeq == 9);
    CHECK(f.value.step == 400);
    CHECK(f.value.stats.potential == -2.5);
    CHECK(f.value.probeForce == Eigen::Vector3d(-1, 0, 1));
}

TEST_CASE("a draft-0 reader reads today's float32 frame and skips the ids", "[protocol]") {
    const StateFrame f = sampleFrame(6, FrameEncoding::Float32, true, true);
    const Buffer now = encodeStateFrame(f);
    flatbuffers::Verifier verifier(now.data(), now.size());
    REQUIRE(v0::VerifyStateFrameBuffer(verifier));
    const v0::StateFrame* old = v0::GetStateFrame(now.data());
    CHECK(old->frame_seq() == f.frameSeq);
    CHECK(old->frame_particle_count() == 6);
    CHECK(std::vector<float>(old->positions()->begin(), old->positions()->end()) == f.positions);
    CHECK(std::vector<float>(old->normals()->begin(), old->normals()->end()) == f.normals);
    CHECK(std::vector<std::uint8_t>(old->species()->begin(), old->species()->end()) == f.species);
    CHECK(old->stats()->pressure() == f.stats.pressure);
}

TEST_CASE("a draft-0 reader finds no positions in a quantised frame", "[protocol]") {
    // Quantised frames need a version-1 reader: the server sends them only to clients whose
    // Hello says protocol_version >= 1. An old reader sees the count but no float arrays.
    const Buffer now = encodeStateFrame(sampleFrame(6, FrameEncoding::Quantised16, true, false));
    flatbuffers::Verifier verifier(now.data(), now.size());
    REQUIRE(v0::VerifyStateFrameBuffer(verifier));
    const v0::StateFrame* old = v0::GetStateFrame(now.data());
    CHECK(old->species()->size() == 6);
    CHECK(old->positions() == nullptr);
    CHECK(old->normals() == nullptr);
}
