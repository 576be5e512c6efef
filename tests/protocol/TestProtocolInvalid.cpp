// Buffers that pass the FlatBuffers verifier but break a rule of the protocol (built here with
// the generated code, since the encoders refuse such values), and encoders refusing bad values.
#include "ProtocolSamples.hpp"
#include "codec/Validate.hpp"
#include "command_generated.h"
#include "frame_generated.h"
#include "hello_generated.h"
#include "map_edits_generated.h"
#include "probe_generated.h"
#include "scene_generated.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

using namespace bop::protocol;
using namespace bop::protocol::samples;

namespace {

// A frame chunk with arrays as given; empty arrays are left out.
struct RawFrame {
    std::uint32_t chunkIndex = 0, chunkCount = 1, frameCount = 4, first = 0;
    std::uint8_t encoding = 0;
    bool bounds = false;
    double hiX = 1;  // quant_hi.x, length
    std::vector<float> positions = std::vector<float>(12, 0.5f), normals;
    std::vector<std::uint8_t> species = std::vector<std::uint8_t>(4, 1);  // species 1
    std::vector<std::uint64_t> ids;
    std::vector<std::uint16_t> qpositions, qnormals;
};

Buffer build(const RawFrame& r) {
    flatbuffers::FlatBufferBuilder fbb;
    const auto vec = [&fbb](const auto& v) { return v.empty() ? 0 : fbb.CreateVector(v).o; };
    const auto positions = vec(r.positions), normals = vec(r.normals), species = vec(r.species), ids = vec(r.ids),
               qpositions = vec(r.qpositions), qnormals = vec(r.qnormals);
    const bop::wire::Vec3 lo(0, 0, 0), hi(r.hiX, 1, 1);
    bop::wire::StateFrameBuilder b(fbb);
    b.add_chunk_index(r.chunkIndex);
    b.add_chunk_count(r.chunkCount);
    b.add_frame_particle_count(r.frameCount);
    b.add_first_index(r.first);
    b.add_encoding(bop::wire::FrameEncoding(r.encoding));
    if (r.bounds) {
        b.add_quant_lo(&lo);
        b.add_quant_hi(&hi);
    }
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_POSITIONS, flatbuffers::Offset<void>(positions));
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_NORMALS, flatbuffers::Offset<void>(normals));
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_SPECIES, flatbuffers::Offset<void>(species));
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_IDS, flatbuffers::Offset<void>(ids));
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_QPOSITIONS, flatbuffers::Offset<void>(qpositions));
    b.fbb_.AddOffset(bop::wire::StateFrame::VT_QNORMALS, flatbuffers::Offset<void>(qnormals));
    bop::wire::FinishStateFrameBuffer(fbb, b.Finish());
    return Buffer(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

DecodeError frameError(const RawFrame& r, int speciesCount = 0) {
    const Buffer b = build(r);
    FrameLimits limits;
    limits.speciesCount = speciesCount;
    return decodeStateFrame(b.data(), b.size(), limits).error;
}

Buffer finish(flatbuffers::FlatBufferBuilder& fbb) {
    return Buffer(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

}  // namespace

TEST_CASE("frame chunks with inconsistent arrays are refused", "[protocol]") {
    REQUIRE(frameError(RawFrame{}) == DecodeError::None);  // the base case is valid

    RawFrame r;
    r.positions.pop_back();
    CHECK(frameError(r) == DecodeError::BadLength);
    r = {};
    r.normals.assign(15, 0.0f);
    CHECK(frameError(r) == DecodeError::BadLength);
    r.normals.assign(12, 0.0f);
    CHECK(frameError(r) == DecodeError::None);
    r.ids = {1, 2, 3};
    CHECK(frameError(r) == DecodeError::BadLength);
    r = {};
    r.qpositions.assign(12, 7);
    CHECK(frameError(r) == DecodeError::BadLength);  // quantised arrays in a float32 chunk

    RawFrame q;
    q.encoding = 1;
    q.bounds = true;
    q.positions.clear();
    q.qpositions.assign(12, 7);
    CHECK(frameError(q) == DecodeError::None);
    q.qnormals.assign(9, 0);
    CHECK(frameError(q) == DecodeError::BadLength);
    q.qnormals.assign(8, 0);
    CHECK(frameError(q) == DecodeError::None);
    q.qpositions.pop_back();
    CHECK(frameError(q) == DecodeError::BadLength);
    q.qpositions.push_back(0);
    q.bounds = false;
    CHECK(frameError(q) == DecodeError::MissingField);
    q.bounds = true;
    q.hiX = 0;  // lo.x = hi.x
    CHECK(frameError(q) == DecodeError::OutOfRange);
    q.hiX = 1e300;  // decoded positions would overflow float32
    CHECK(frameError(q) == DecodeError::OutOfRange);
    q.hiX = std::numeric_limits<double>::quiet_NaN();
    CHECK(frameError(q) == DecodeError::NotFinite);
    q.hiX = 1;
    q.encoding = 9;
    CHECK(frameError(q) == DecodeError::Unsupported);

    // An empty quantised chunk may leave every array out (a fuzz finding: qpositions was read
    // without a check that it is there).
    RawFrame empty;
    empty.encoding = 1;
    empty.bounds = true;
    empty.frameCount = 0;
    empty.positions.clear();
    empty.species.clear();
    const Buffer b = build(empty);
    const auto decoded = decodeStateFrame(b.data(), b.size(), FrameLimits{});
    CHECK(decoded.error == DecodeError::None);
}

TEST_CASE("frame chunks out of range are refused", "[protocol]") {
    RawFrame r;
    r.chunkIndex = 1;
    CHECK(frameError(r) == DecodeError::OutOfRange);
    r.chunkCount = 2;
    CHECK(frameError(r) == DecodeError::None);
    r.chunkCount = 0;
    r.chunkIndex = 0;
    CHECK(frameError(r) == DecodeError::OutOfRange);
    r = {};
    r.first = 1;  // particles 1..4 of a 4-particle frame
    CHECK(frameError(r) == DecodeError::OutOfRange);
    r.frameCount = 5;
    CHECK(frameError(r) == DecodeError::None);
    r = {};
    r.species[2] = 0;
    CHECK(frameError(r) == DecodeError::OutOfRange);
    r.species[2] = 4;
    CHECK(frameError(r, 3) == DecodeError::OutOfRange);  // the scene has 3 species
    CHECK(frameError(r, 4) == DecodeError::None);
    r.positions[5] = std::numeric_limits<float>::quiet_NaN();
    CHECK(frameError(r) == DecodeError::NotFinite);
    r.positions[5] = std::numeric_limits<float>::infinity();
    CHECK(frameError(r) == DecodeError::NotFinite);
}

TEST_CASE("small messages breaking a rule are refused with a reason", "[protocol]") {
    using namespace bop::wire;
    flatbuffers::FlatBufferBuilder fbb;
    const Vec3 at(1, 2, 3);

    FinishProbeBuffer(fbb, CreateProbe(fbb, 1, 2, &at, true, 0.0, 1.0));  // k0 = 0
    Buffer b = finish(fbb);
    Decoded<bop::protocol::Probe> p = decodeProbe(b.data(), b.size());
    CHECK(p.error == DecodeError::OutOfRange);
    CHECK(p.message == "Probe.k0: 0 outside 0.1..10");
    fbb.Clear();
    FinishProbeBuffer(fbb, CreateProbe(fbb, 1, 2, nullptr, true));  // no position
    b = finish(fbb);
    CHECK(decodeProbe(b.data(), b.size()).error == DecodeError::MissingField);
    fbb.Clear();
    const Vec3 nan(0, std::numeric_limits<double>::quiet_NaN(), 0);
    FinishProbeBuffer(fbb, CreateProbe(fbb, 1, 2, &nan, true));
    b = finish(fbb);
    CHECK(decodeProbe(b.data(), b.size()).error == DecodeError::NotFinite);

    fbb.Clear();
    FinishHelloBuffer(fbb, CreateHello(fbb, 0));  // no protocol version
    b = finish(fbb);
    CHECK(decodeHello(b.data(), b.size()).error == DecodeError::MissingField);
    fbb.Clear();
    FinishHelloBuffer(fbb, CreateHello(fbb, 1, bop::wire::Role(9)));
    b = finish(fbb);
    CHECK(decodeHello(b.data(), b.size()).error == DecodeError::Unsupported);

    fbb.Clear();
    FinishCommandBuffer(fbb, CreateCommand(fbb, 5, bop::wire::CommandBody::NONE));
    b = finish(fbb);
    CHECK(decodeCommand(b.data(), b.size()).error == DecodeError::MissingField);
    fbb.Clear();
    const auto later = CreateSwitchMapFrame(fbb, 1).Union();  // a body type from a later version
    FinishCommandBuffer(fbb, CreateCommand(fbb, 5, bop::wire::CommandBody(42), later));
    b = finish(fbb);
    const Decoded<bop::protocol::Command> c = decodeCommand(b.data(), b.size());
    CHECK(c.error == DecodeError::Unsupported);
    CHECK(c.message.find("42") != std::string::npos);
    fbb.Clear();
    const auto param = CreateSetParameterDirect(fbb, std::string(65, 'x').c_str(), 0, 0, 1.0).Union();
    FinishCommandBuffer(fbb, CreateCommand(fbb, 5, bop::wire::CommandBody::SetParameter, param));
    b = finish(fbb);
    CHECK(decodeCommand(b.data(), b.size()).error == DecodeError::BadLength);
    fbb.Clear();
    const auto seed = CreateSeedParticle(fbb, 0, &at).Union();  // species 0
    FinishCommandBuffer(fbb, CreateCommand(fbb, 5, bop::wire::CommandBody::SeedParticle, seed));
    b = finish(fbb);
    CHECK(decodeCommand(b.data(), b.size()).error == DecodeError::OutOfRange);
}

TEST_CASE("map edits that break a rule, or would take a client's memory, are refused", "[protocol][cut]") {
    using namespace bop::wire;
    flatbuffers::FlatBufferBuilder fbb;
    const Vec3 a(1, 2, 3), b(4, 5, 6);
    const auto decode = [&](std::vector<flatbuffers::Offset<bop::wire::MapEdit>> edits, std::uint32_t first,
                            std::uint32_t total) {
        FinishMapEditsBuffer(fbb, CreateMapEdits(fbb, first, total, fbb.CreateVector(edits)));
        const Buffer buf = finish(fbb);
        fbb.Clear();
        return decodeMapEdits(buf.data(), buf.size());
    };
    // A bomb: 4,000 edits sharing one vector of 65,536 voxels pass the verifier in half a MiB,
    // yet would decode to 2 GiB. Refused before a voxel is copied.
    const auto shared = fbb.CreateVector(std::vector<std::uint64_t>(65536, 7));
    std::vector<flatbuffers::Offset<bop::wire::MapEdit>> bomb;
    for (int k = 0; k < 4000; ++k) bomb.push_back(CreateMapEdit(fbb, &a, &b, 0, shared));
    const auto refused = decode(bomb, 0, 4000);
    CHECK(refused.error == DecodeError::TooLarge);
    CHECK(refused.message.find("MapEdits.edits") != std::string::npos);
    // Voxels out of order, a blade with voxels, nothing at all, edits beyond the total, a NaN.
    const auto unordered = fbb.CreateVector(std::vector<std::uint64_t>{5, 9, 9});
    CHECK(decode({CreateMapEdit(fbb, &a, &b, 0, unordered)}, 0, 1).message == "MapEdits.edits.voxels: not increasing");
    const auto some = fbb.CreateVector(std::vector<std::uint64_t>{5, 9});
    CHECK(decode({CreateMapEdit(fbb, &a, &b, 1.5, some)}, 0, 1).error == DecodeError::BadLength);
    CHECK(decode({CreateMapEdit(fbb, &a, &b, 0)}, 0, 1).error == DecodeError::BadLength);
    CHECK(decode({CreateMapEdit(fbb, &a, &b, 1.5)}, 4, 4).message.find("MapEdits.first") == 0);
    const Vec3 nan(0, std::numeric_limits<double>::quiet_NaN(), 0);
    CHECK(decode({CreateMapEdit(fbb, &nan, &b, 1.5)}, 0, 1).error == DecodeError::NotFinite);
    CHECK(decode({CreateMapEdit(fbb, nullptr, &b, 1.5)}, 0, 1).error == DecodeError::MissingField);
    CHECK(decode({CreateMapEdit(fbb, &a, &b, 1.5)}, 0, 1).ok());

    // Found by the fuzzer: a buffer whose voxel vector starts 4 bytes off an 8-byte boundary (the
    // verifier checks only its length's alignment) and whose blade is out of range. The voxels
    // are copied without a misaligned load (UBSan in CI), then the value is refused.
    static const std::uint8_t offVoxels[] = {
        0x14, 0x00, 0x00, 0x00, 0x42, 0x4d, 0x45, 0x44, 0x00, 0x00, 0x0a, 0x00, 0x10, 0x00, 0x04, 0x00, 0x08, 0x00,
        0x0c, 0x00, 0x0a, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x09, 0x00, 0x00, 0x40, 0x04, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x00, 0x00, 0x84, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x0c, 0x00, 0x38, 0x00, 0x04, 0x00,
        0x1c, 0x00, 0x00, 0x00, 0x34, 0x00, 0x0c, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x05, 0x00, 0x00, 0x00, 0x03, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x70, 0x11, 0x01, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x07, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x70, 0x11, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x0a, 0x00, 0x3c, 0x00, 0x04, 0x00, 0x1c, 0x00, 0x34, 0x00, 0x0a, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0xf8, 0x3f, 0x00, 0x00, 0x27, 0xfd, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0a, 0x00, 0x10, 0x00, 0x04, 0x00, 0x08, 0x00,
        0x0c, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0xbf, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xe8, 0x3f,
    };
    const Decoded<bop::protocol::MapEdits> off = decodeMapEdits(offVoxels, sizeof offVoxels);
    CHECK(off.error == DecodeError::OutOfRange);
    CHECK(off.message.find("MapEdits.edits.to") == 0);
}

TEST_CASE("scene info beyond its limits is refused", "[protocol]") {
    using namespace bop::wire;
    const auto sceneWith = [](int species) {
        flatbuffers::FlatBufferBuilder fbb;
        std::vector<flatbuffers::Offset<Species>> list;
        for (int k = 0; k < species; ++k) list.push_back(CreateSpeciesDirect(fbb, "s"));
        const Vec3 lo(0, 0, 0), hi(1, 1, 1);
        FinishSceneInfoBuffer(fbb, CreateSceneInfoDirect(fbb, 1, &list, &lo, &hi, nullptr, nullptr, 0, 1.7, 0, 0.01));
        return finish(fbb);
    };
    Buffer b = sceneWith(255);
    CHECK(decodeSceneInfo(b.data(), b.size()).ok());
    b = sceneWith(256);  // within the verifier's table limit, over the species limit
    CHECK(decodeSceneInfo(b.data(), b.size()).error == DecodeError::BadLength);
    b = sceneWith(300);  // more tables than the verifier is allowed to visit
    REQUIRE(b.size() <= kMaxSceneInfoBytes);
    CHECK(decodeSceneInfo(b.data(), b.size()).error == DecodeError::Malformed);

    bop::protocol::SceneInfo s = sampleScene();
    s.boxHi.y() = s.boxLo.y();
    CHECK_THROWS_AS(encodeSceneInfo(s), EncodeError);

    // The unit system's mass and time are checked whether or not the units are physical: a NaN
    // there (found by fuzzing) decoded to a value that is not equal to itself.
    for (const bool physical : {false, true})
        for (double bop::UnitSystem::*field : {&bop::UnitSystem::massKg, &bop::UnitSystem::timeS}) {
            bop::protocol::SceneInfo u = sampleScene();
            u.unitSystem.physical = physical;
            u.unitSystem.*field = std::numeric_limits<double>::quiet_NaN();
            const Validation v = validate(u);
            CHECK(!v.ok());
            CHECK(v.message.find(field == &bop::UnitSystem::massKg ? "mass_kg" : "time_s") != std::string::npos);
        }
}

TEST_CASE("scene tunables of the wrong size, negative damping or k0 <= 0 are refused, naming the field", "[protocol]") {
    const bop::protocol::SceneInfo good = sampleScene(3);
    REQUIRE(validate(good).ok());
    const auto refused = [](bop::protocol::SceneInfo s, DecodeError e, const std::string& field) {
        const Validation v = validate(s);
        INFO(v.message);
        CHECK(v.error == e);
        CHECK(v.message.find(field) != std::string::npos);
    };
    bop::protocol::SceneInfo s = good;
    s.tunables.coPlanar.pop_back();  // 8 values for 3 species
    refused(s, DecodeError::BadLength, "tunables.co_planar");
    s = good;
    s.tunables.dragW.push_back(1);
    refused(s, DecodeError::BadLength, "tunables.drag_w");
    s = good;
    s.tunables.dragV[1] = -0.5;
    refused(s, DecodeError::OutOfRange, "tunables.drag_v");
    s = good;
    s.tunables.k0 = 0;
    refused(s, DecodeError::OutOfRange, "tunables.k0");
    s = good;
    s.tunables.lj[4] = std::nan("");
    refused(s, DecodeError::NotFinite, "tunables.lj");
    s = good;
    s.probeReach = -1;
    refused(s, DecodeError::OutOfRange, "probe_reach");
    s = sampleScene(17);  // matrices only up to 16 species, so that SceneInfo stays under its cap
    s.tunables.dragV.assign(17, 1.0);
    refused(s, DecodeError::BadLength, "tunables.drag_v");
}

TEST_CASE("encoders refuse values a decoder would refuse", "[protocol]") {
    bop::protocol::Probe p = sampleProbe();
    p.k0 = -1;
    CHECK_THROWS_AS(encodeProbe(p), EncodeError);
    CHECK_THROWS_AS(encodeCommand({1, SeedParticle{0, {0, 0, 0}}}), EncodeError);
    CHECK_THROWS_AS(encodeCommand({1, RunControl{RunAction::SingleStep, 0}}), EncodeError);
    StateFrame f = sampleFrame(10, FrameEncoding::Float32, true, false);
    f.normals.pop_back();
    CHECK_THROWS_AS(encodeStateFrame(f), EncodeError);
    f = sampleFrame(10, FrameEncoding::Float32, true, false);
    f.chunkIndex = 1;
    try {
        encodeStateFrame(f);
        FAIL("no exception");
    } catch (const EncodeError& e) {
        CHECK(std::string(e.what()) == "cannot encode StateFrame.chunk_index: 1 not below chunk_count 1");
    }
}
