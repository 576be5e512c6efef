// Every message survives encode -> decode unchanged; frames split into chunks and join again;
// the largest valid messages stay within their caps.
#include "ProtocolSamples.hpp"
#include "codec/BufferPool.hpp"
#include "codec/Quantise.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

using namespace bop::protocol;
using namespace bop::protocol::samples;

TEST_CASE("handshake messages round trip", "[protocol]") {
    const Buffer hello = encodeHello(sampleHello());
    const Decoded<Hello> h = decodeHello(hello.data(), hello.size());
    REQUIRE(h.ok());
    CHECK(same(h.value, sampleHello()));
    CHECK(h.value.protocolVersion == kProtocolVersion);
    CHECK(h.value.role == Role::Haptic);

    const Buffer scene = encodeSceneInfo(sampleScene());
    const Decoded<SceneInfo> s = decodeSceneInfo(scene.data(), scene.size());
    REQUIRE(s.ok());
    CHECK(same(s.value, sampleScene()));
    CHECK(s.value.species[1].kind == SpeciesKind::Volume);
    CHECK(s.value.r0 == Approx(1.7320508075688772).epsilon(1e-15));
}

TEST_CASE("probe and feedback round trip within their caps", "[protocol]") {
    const Buffer probe = encodeProbe(sampleProbe());
    const Decoded<Probe> p = decodeProbe(probe.data(), probe.size());
    REQUIRE(p.ok());
    CHECK(same(p.value, sampleProbe()));
    CHECK(probe.size() <= kMaxProbeBytes);

    const Buffer feedback = encodeFeedback(sampleFeedback());
    const Decoded<Feedback> f = decodeFeedback(feedback.data(), feedback.size());
    REQUIRE(f.ok());
    CHECK(same(f.value, sampleFeedback()));
    CHECK(feedback.size() <= kMaxFeedbackBytes);

    // Default values are written too, so a probe has one size whatever it holds.
    CHECK(encodeProbe(Probe{}).size() == probe.size());
}

TEST_CASE("every command and the reply round trip", "[protocol]") {
    for (const Command& c : sampleCommands()) {
        const Buffer b = encodeCommand(c);
        const Decoded<Command> d = decodeCommand(b.data(), b.size());
        INFO("command body " << c.body.index() << ": " << d.message);
        REQUIRE(d.ok());
        CHECK(same(d.value, c));
        CHECK(messageKind(b.data(), b.size()) == MessageKind::Command);
    }
    const Buffer r = encodeCommandReply(sampleReply());
    const Decoded<CommandReply> d = decodeCommandReply(r.data(), r.size());
    REQUIRE(d.ok());
    CHECK(same(d.value, sampleReply()));
}

TEST_CASE("float32 frames round trip exactly", "[protocol]") {
    for (const bool normals : {false, true})
        for (const bool ids : {false, true}) {
            const StateFrame f = sampleFrame(100, FrameEncoding::Float32, normals, ids);
            const Buffer b = encodeStateFrame(f);
            const Decoded<StateFrame> d = decodeStateFrame(b.data(), b.size());
            INFO("normals " << normals << " ids " << ids << ": " << d.message);
            REQUIRE(d.ok());
            CHECK(same(d.value, f));
            CHECK(d.value.count() == 100);
        }
    // An empty frame is a valid frame.
    const Buffer empty = encodeStateFrame(sampleFrame(0, FrameEncoding::Float32, true, true));
    const Decoded<StateFrame> d = decodeStateFrame(empty.data(), empty.size());
    REQUIRE(d.ok());
    CHECK(d.value.count() == 0);
    CHECK(d.value.positions.empty());
}

TEST_CASE("quantised frames decode within the stated bounds", "[protocol]") {
    const StateFrame f = sampleFrame(2000, FrameEncoding::Quantised16, true, true);
    const Buffer b = encodeStateFrame(f);
    const Decoded<StateFrame> d = decodeStateFrame(b.data(), b.size());
    REQUIRE(d.ok());
    const StateFrame& g = d.value;
    REQUIRE(g.positions.size() == f.positions.size());
    REQUIRE(g.normals.size() == f.normals.size());
    CHECK(g.encoding == FrameEncoding::Quantised16);
    CHECK(g.species == f.species);
    CHECK(g.ids == f.ids);
    CHECK(g.step == f.step);
    const Eigen::Vector3d bound = positionErrorBound(f.quantLo, f.quantHi);
    double worstPos = 0, worstAngle = 0;
    for (std::size_t i = 0; i < f.count(); ++i)
        for (int a = 0; a < 3; ++a) {
            const double err = std::abs(double(g.positions[3 * i + a]) - double(f.positions[3 * i + a]));
            worstPos = std::max(worstPos, err / bound[a]);
        }
    for (std::size_t i = 0; i < f.count(); ++i) {
        const Eigen::Vector3d n0(f.normals[3 * i], f.normals[3 * i + 1], f.normals[3 * i + 2]);
        const Eigen::Vector3d n1(g.normals[3 * i], g.normals[3 * i + 1], g.normals[3 * i + 2]);
        worstAngle = std::max(worstAngle, std::atan2(n0.cross(n1).norm(), n0.dot(n1)));
    }
    CHECK(worstPos <= 1.0);  // every coordinate within its axis's bound
    CHECK(worstPos > 0.5);   // and the bound is not loose: errors reach over half of it
    CHECK(worstAngle <= kOctMaxAngleRad);
}

TEST_CASE("a frame split in chunks joins back to the same frame", "[protocol]") {
    for (const FrameEncoding enc : {FrameEncoding::Float32, FrameEncoding::Quantised16}) {
        const StateFrame f = sampleFrame(10000, enc, true, true);
        const std::size_t cap = 64 * 1024;
        const std::vector<Buffer> chunks = encodeStateFrameChunks(f, cap);
        const std::size_t bpp = bytesPerParticle(enc, true, true);
        const std::size_t perChunk = (cap - 1024) / bpp;
        CHECK(chunks.size() == (10000 + perChunk - 1) / perChunk);
        StateFrame joined;
        FrameLimits limits;
        limits.maxChunkBytes = cap;
        limits.speciesCount = 4;
        for (std::size_t c = 0; c < chunks.size(); ++c) {
            CHECK(chunks[c].size() <= cap);
            const Decoded<StateFrame> d = decodeStateFrame(chunks[c].data(), chunks[c].size(), limits);
            REQUIRE(d.ok());
            CHECK(d.value.chunkIndex == c);
            CHECK(d.value.chunkCount == chunks.size());
            CHECK(d.value.frameSeq == f.frameSeq);
            CHECK(d.value.firstIndex == joined.species.size());
            CHECK(d.value.frameParticleCount == 10000);
            joined.positions.insert(joined.positions.end(), d.value.positions.begin(), d.value.positions.end());
            joined.normals.insert(joined.normals.end(), d.value.normals.begin(), d.value.normals.end());
            joined.species.insert(joined.species.end(), d.value.species.begin(), d.value.species.end());
            joined.ids.insert(joined.ids.end(), d.value.ids.begin(), d.value.ids.end());
        }
        // Chunking changes nothing: the joined arrays equal those of the frame sent whole.
        const Buffer whole = encodeStateFrame(f);
        const Decoded<StateFrame> w = decodeStateFrame(whole.data(), whole.size());
        REQUIRE(w.ok());
        CHECK(joined.positions == w.value.positions);
        CHECK(joined.normals == w.value.normals);
        CHECK(joined.species == f.species);
        CHECK(joined.ids == f.ids);
    }
    CHECK_THROWS_AS(encodeStateFrameChunks(sampleFrame(10, FrameEncoding::Float32, true, false), 1000), EncodeError);
    // One particle per chunk would need 5000 chunks, more than a receiver accepts; two fit.
    const StateFrame big = sampleFrame(5000, FrameEncoding::Float32, true, false);
    CHECK_THROWS_AS(encodeStateFrameChunks(big, 1024 + 25), EncodeError);
    CHECK(encodeStateFrameChunks(big, 1024 + 2 * 25).size() == 2500);
}

TEST_CASE("the largest valid messages fit their caps", "[protocol]") {
    Hello h = sampleHello();
    h.clientName = std::string(kMaxNameBytes, 'h');
    CHECK(encodeHello(h).size() <= kMaxHelloBytes);

    SceneInfo s = sampleScene(kMaxSpecies);
    for (SpeciesInfo& sp : s.species) sp.name = std::string(kMaxNameBytes, 's');
    s.units = std::string(kMaxTextBytes, 'u');
    s.endpoints.frameEndpoint = std::string(kMaxEndpointBytes, 'e');
    const Buffer scene = encodeSceneInfo(s);
    CHECK(scene.size() <= kMaxSceneInfoBytes);
    const Decoded<SceneInfo> d = decodeSceneInfo(scene.data(), scene.size());
    REQUIRE(d.ok());
    CHECK(d.value.species.size() == 255);

    CHECK(encodeCommand({1, Record{true, std::string(kMaxPathBytes, 'p')}}).size() <= kMaxCommandBytes);
    CHECK(encodeCommand({1, SetParameter{std::string(kMaxNameBytes, 'n'), 255, 255, 1.0}}).size() <= kMaxCommandBytes);
    CHECK(encodeCommandReply({1, ReplyStatus::Ok, 2, std::string(kMaxTextBytes, 'm')}).size() <= kMaxReplyBytes);
}

TEST_CASE("message kinds are read from the file identifier", "[protocol]") {
    for (const Sample& s : allSamples()) {
        CHECK(messageKind(s.bytes.data(), s.bytes.size()) == s.kind);
        CHECK(std::string(fileIdentifier(s.kind)) == std::string(reinterpret_cast<const char*>(s.bytes.data()) + 4, 4));
    }
    const Buffer probe = encodeProbe(sampleProbe());
    CHECK(messageKind(probe.data(), 7) == MessageKind::Unknown);
    CHECK(messageKind(nullptr, 100) == MessageKind::Unknown);
    const std::uint8_t junk[8] = {8, 0, 0, 0, 'X', 'Y', 'Z', 'W'};
    CHECK(messageKind(junk, sizeof junk) == MessageKind::Unknown);
    CHECK(std::string(fileIdentifier(MessageKind::Unknown)).empty());
}

TEST_CASE("chunks encoded into pooled buffers reuse their memory and carry the same bytes", "[protocol]") {
    const StateFrame f = sampleFrame(5000, FrameEncoding::Quantised16, true, false);
    const std::vector<Buffer> plain = encodeStateFrameChunks(f, 16 * 1024);
    REQUIRE(plain.size() > 2);
    BufferPool pool(plain.size());
    std::vector<Buffer> first = encodeStateFrameChunks(f, 16 * 1024, &pool);
    CHECK(first == plain);
    std::vector<const std::uint8_t*> memory;
    for (Buffer& b : first) {
        memory.push_back(b.data());
        pool.give(std::move(b));
    }
    CHECK(pool.kept() == plain.size());
    const std::vector<Buffer> again = encodeStateFrameChunks(f, 16 * 1024, &pool);
    CHECK(again == plain);
    CHECK(pool.kept() == 0);
    for (const Buffer& b : again) CHECK(std::find(memory.begin(), memory.end(), b.data()) != memory.end());
    BufferPool small(1);  // keeps at most one
    small.give(Buffer(10));
    small.give(Buffer(20));
    CHECK(small.kept() == 1);
}
