// The channels recordings add for Foxglove (recording/FoxgloveMessages.hpp, FoxgloveChannels.hpp),
// read back with the C++ code flatc generates from schemas/foxglove: every buffer verifies, and
// its content is the frame's (positions bit for bit, species colours, discs facing the normals,
// the probe, the transform, the plotted numbers). tests/cli/foxglove_cli.sh checks the same
// recordings with Foxglove's own libraries and published schemas.
#include "ProtocolSamples.hpp"
#include "TestUtil.hpp"
#include "codec/Codec.hpp"
#include "foxglove_types_generated.h"
#include "frame_stats_generated.h"
#include "recording/FoxgloveChannels.hpp"
#include "recording/FoxgloveMessages.hpp"
#include "recording/McapReader.hpp"
#include "recording/SessionTopics.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <cstring>

using namespace bop::protocol;
namespace fg = ::foxglove;

namespace {

constexpr std::uint64_t kTime = 1'765'000'000'123'456'789ull;

template <class T>
const T* verified(const Buffer& b) {
    flatbuffers::Verifier v(b.data(), b.size());
    REQUIRE(v.VerifyBuffer<T>(nullptr));
    return flatbuffers::GetRoot<T>(b.data());
}
template <class T>
const T* verified(Buffer&&) = delete;  // the result points into the buffer: keep it alive

// A scene whose species 1 and 3 are surfaces, 2 and 4 volumes.
SceneInfo scene() {
    SceneInfo s = samples::sampleScene(4);
    for (std::size_t k = 0; k < s.species.size(); ++k) {
        s.species[k].kind = k % 2 ? SpeciesKind::Volume : SpeciesKind::Surface;
        s.species[k].rgba = {std::uint8_t(10 * k), 200, std::uint8_t(255 - k), 255};
    }
    s.boxLo = {-2, 0, 4};
    s.boxHi = {6, 10, 8};
    return s;
}

StateFrame frame(std::size_t n) {
    StateFrame f = samples::sampleFrame(n, FrameEncoding::Float32, true, true);
    for (std::size_t i = 0; i < n; ++i) f.species[i] = std::uint8_t(1 + i % 4);
    return f;
}

Eigen::Vector3d rotate(const fg::Quaternion* q, const Eigen::Vector3d& v) {
    return Eigen::Quaterniond(q->w(), q->x(), q->y(), q->z()) * v;
}

}  // namespace

TEST_CASE("foxglove point cloud holds every particle's position, colour and species", "[foxglove]") {
    const SceneInfo s = scene();
    const StateFrame f = frame(500);
    const Buffer b = fox::pointCloud(f, s, kTime);
    const auto* pc = verified<fg::PointCloud>(b);
    CHECK(pc->timestamp()->sec() == 1'765'000'000u);
    CHECK(pc->timestamp()->nsec() == 123'456'789u);
    CHECK(pc->frame_id()->str() == fox::kFrameBop);
    REQUIRE(pc->point_stride() == 17);
    REQUIRE(pc->data()->size() == 500 * 17);
    std::map<std::string, std::pair<std::uint32_t, fg::NumericType>> fields;
    for (const auto* x : *pc->fields()) fields[x->name()->str()] = {x->offset(), x->type()};
    CHECK(fields.at("x") == std::pair{0u, fg::NumericType::FLOAT32});
    CHECK(fields.at("z") == std::pair{8u, fg::NumericType::FLOAT32});
    CHECK(fields.at("alpha") == std::pair{15u, fg::NumericType::UINT8});
    CHECK(fields.at("species") == std::pair{16u, fg::NumericType::UINT8});
    for (std::size_t i = 0; i < 500; ++i) {
        const std::uint8_t* p = pc->data()->data() + 17 * i;
        REQUIRE(std::memcmp(p, &f.positions[3 * i], 12) == 0);
        const auto& rgba = s.species[f.species[i] - 1].rgba;
        REQUIRE(std::memcmp(p + 12, rgba.data(), 4) == 0);
        REQUIRE(p[16] == f.species[i]);
    }
}

TEST_CASE("foxglove surfels are discs facing each surface particle's normal", "[foxglove]") {
    const SceneInfo s = scene();
    StateFrame f = frame(400);
    f.normals[0] = 0, f.normals[1] = 0, f.normals[2] = -1;  // straight down: the half-turn case
    const Buffer ub = fox::surfels(f, s, kTime);
    const auto* u = verified<fg::SceneUpdate>(ub);
    REQUIRE(u->entities()->size() == 1);
    const auto* e = u->entities()->Get(0);
    CHECK(e->id()->str() == "surfels");
    CHECK(e->frame_id()->str() == fox::kFrameBop);
    REQUIRE(e->cylinders()->size() == 200);  // species 1 and 3 of 1..4
    std::size_t k = 0;
    for (std::size_t i = 0; i < 400; ++i) {
        if (f.species[i] % 2 == 0) continue;
        const auto* c = e->cylinders()->Get(flatbuffers::uoffset_t(k++));
        const Eigen::Vector3d n =
            Eigen::Vector3d(f.normals[3 * i], f.normals[3 * i + 1], f.normals[3 * i + 2]).normalized();
        REQUIRE((rotate(c->pose()->orientation(), Eigen::Vector3d::UnitZ()) - n).norm() < 1e-9);
        REQUIRE(c->pose()->position()->x() == double(f.positions[3 * i]));
        REQUIRE(c->size()->x() == s.r0);
        REQUIRE(c->size()->z() == s.r0 / 8);
        REQUIRE(c->color()->g() == Approx(200 / 255.0));
    }
    // Past kMaxDiscs surface particles, every k-th is drawn and the entity says which k.
    const StateFrame big = frame(2 * fox::kMaxDiscs + 8);
    const Buffer bigBuffer = fox::surfels(big, s, kTime);
    const auto* e2 = verified<fg::SceneUpdate>(bigBuffer)->entities()->Get(0);
    CHECK(e2->cylinders()->size() == (fox::kMaxDiscs + 4) / 2);  // 20,004 surface particles: every 2nd
    CHECK(e2->metadata()->Get(0)->value()->str() == "2");
}

TEST_CASE("foxglove probe, transform and plotted numbers follow the frame", "[foxglove]") {
    const SceneInfo s = scene();
    StateFrame f = frame(10);
    f.probeActive = true;
    f.probePosition = {1, 2, 3};
    f.probeForce = {0, 3, 4};
    const Buffer pb = fox::probe(f, s, kTime);
    const auto* e = verified<fg::SceneUpdate>(pb)->entities()->Get(0);
    CHECK(e->id()->str() == "probe");
    REQUIRE(e->spheres()->size() == 1);
    CHECK(e->spheres()->Get(0)->pose()->position()->z() == 3);
    REQUIRE(e->arrows()->size() == 1);
    const Eigen::Vector3d along = rotate(e->arrows()->Get(0)->pose()->orientation(), Eigen::Vector3d::UnitX());
    CHECK((along - Eigen::Vector3d(0, 0.6, 0.8)).norm() < 1e-12);
    f.probeActive = false;
    const Buffer gb = fox::probe(f, s, kTime);
    const auto* gone = verified<fg::SceneUpdate>(gb);
    CHECK(gone->entities()->size() == 0);
    REQUIRE(gone->deletions()->size() == 1);
    CHECK(gone->deletions()->Get(0)->id()->str() == "probe");

    const Buffer tb = fox::worldToBop(s, kTime);
    const auto* t = verified<fg::FrameTransform>(tb);
    CHECK(t->parent_frame_id()->str() == "world");
    CHECK(t->child_frame_id()->str() == "bop");
    CHECK(t->translation()->x() == -2);
    CHECK(t->translation()->y() == -5);
    CHECK(t->translation()->z() == -6);
    CHECK(t->rotation()->w() == 1);

    f.stats.kinetic = 1.5;
    f.stats.potential = -4;
    f.probeActive = true;
    const Buffer rb = fox::frameStats(f, s, kTime);
    const auto* row = verified<bop::plot::FrameStats>(rb);
    CHECK(row->total_energy() == -2.5);
    CHECK(row->probe_force() == 5);
    CHECK(row->probe_force_z() == 4);
    CHECK(row->step() == f.step);
    SceneInfo plain = s;  // a scene without materials: no newtons, no seconds
    plain.unitSystem = bop::UnitSystem{};
    const Buffer plainBuffer = fox::frameStats(f, plain, kTime);
    const auto* plainRow = verified<bop::plot::FrameStats>(plainBuffer);
    CHECK(plainRow->probe_force_n() == 0);
    CHECK(plainRow->sim_time_s() == 0);

    // In physical units: the force in N and the time in s beside the simulation's, and the
    // real-time factor as the frame carries it.
    SceneInfo physical = s;
    physical.unitSystem = bop::UnitSystem::fromModulus(1.5, 2e-6, 5e3, 0.5);
    f.stats.realTimeFactor = 0.75;
    f.simTime = 40;
    const Buffer physicalRow = fox::frameStats(f, physical, kTime);
    const auto* prow = verified<bop::plot::FrameStats>(physicalRow);
    CHECK(prow->probe_force_n() == Approx(5 * physical.unitSystem.forceN()));
    CHECK(prow->sim_time_s() == Approx(40 * physical.unitSystem.timeS));
    CHECK(prow->real_time_factor() == 0.75);
}

TEST_CASE("foxglove channels write one set of messages per whole frame, in chunks or not", "[foxglove]") {
    const bop::test::TempDir dir("foxglove");
    const std::string path = dir.file("fox.mcap");
    const SceneInfo s = scene();
    StateFrame whole = frame(3000);
    {
        bop::recording::McapWriter w(path);
        FoxgloveChannels fox(w, s);
        for (std::uint64_t seq = 1; seq <= 3; ++seq) {
            whole.frameSeq = seq;
            const auto chunks = encodeStateFrameChunks(whole, 20'000);
            REQUIRE(chunks.size() > 2);
            for (std::size_t k = 0; k < chunks.size(); ++k) {
                fox.frameChunk(chunks[k], kTime + seq);
                CHECK(fox.framesWritten() == seq - (k + 1 < chunks.size()));
            }
        }
        w.close();
    }
    const auto f = bop::recording::readMcap(path);
    std::map<std::string, int> perTopic;
    for (const auto& m : f.messages) ++perTopic[f.channel(m.channelId)->topic];
    for (const char* t : {kTopicStats, kTopicParticles, kTopicSurfels, kTopicProbeShape, kTopicTransform})
        CHECK(perTopic[t] == 3);
    for (const auto& m : f.messages)
        if (f.channel(m.channelId)->topic == kTopicParticles) {
            const auto* pc = flatbuffers::GetRoot<fg::PointCloud>(m.data.data());
            CHECK(pc->data()->size() == 3000 * 17);
        }
}
