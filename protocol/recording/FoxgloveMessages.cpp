#include "recording/FoxgloveMessages.hpp"

#include "bop/common/BagColours.hpp"
#include "foxglove_types_generated.h"
#include "frame_stats_generated.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>

namespace bop::protocol::fox {

namespace fg = ::foxglove;
using flatbuffers::FlatBufferBuilder;
using flatbuffers::Offset;

namespace {

fg::Time stamp(std::uint64_t ns) {
    return fg::Time(static_cast<std::uint32_t>(ns / 1'000'000'000u), static_cast<std::uint32_t>(ns % 1'000'000'000u));
}

Offset<fg::Vector3> vec3(FlatBufferBuilder& b, double x, double y, double z) {
    return fg::CreateVector3(b, x, y, z);
}

// Rotation taking the z axis onto the unit vector n: (w, v) = (1 + z.n, z x n), normalised.
Offset<fg::Quaternion> zTo(FlatBufferBuilder& b, const Eigen::Vector3d& n) {
    const double w = 1 + n.z();
    if (w < 1e-9) return fg::CreateQuaternion(b, 1, 0, 0, 0);  // n = -z: half a turn about x
    const double s = std::sqrt(w * w + n.x() * n.x() + n.y() * n.y());
    return fg::CreateQuaternion(b, -n.y() / s, n.x() / s, 0, w / s);
}

Offset<fg::Pose> pose(FlatBufferBuilder& b, const Eigen::Vector3d& at, const Eigen::Vector3d& zAxis) {
    const auto p = vec3(b, at.x(), at.y(), at.z());
    const auto q = zTo(b, zAxis);
    return fg::CreatePose(b, p, q);
}

// The scene's colour of a species (1-based), or the default bag colours.
std::array<std::uint8_t, 4> colourOf(const SceneInfo& scene, std::uint8_t species) {
    if (species >= 1 && species <= scene.species.size()) return scene.species[species - 1].rgba;
    const auto c = defaultSpeciesColour(species);
    return {std::uint8_t(c[0] * 255), std::uint8_t(c[1] * 255), std::uint8_t(c[2] * 255), 255};
}

Offset<fg::Color> colour(FlatBufferBuilder& b, std::array<std::uint8_t, 4> c) {
    return fg::CreateColor(b, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, c[3] / 255.0);
}

bool isSurface(const SceneInfo& scene, std::uint8_t species) {
    return species >= 1 && species <= scene.species.size() && scene.species[species - 1].kind == SpeciesKind::Surface;
}

Buffer finish(FlatBufferBuilder& b) {
    return Buffer(b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize());
}

Buffer sceneUpdate(FlatBufferBuilder& b, const std::vector<Offset<fg::SceneEntity>>& entities,
                   const std::vector<Offset<fg::SceneEntityDeletion>>& deletions) {
    const auto d = b.CreateVector(deletions);
    const auto e = b.CreateVector(entities);
    b.Finish(fg::CreateSceneUpdate(b, d, e));
    return finish(b);
}

}  // namespace

Buffer pointCloud(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs) {
    constexpr std::uint32_t kStride = 17;
    FlatBufferBuilder b(64 + frame.count() * kStride);
    std::vector<std::uint8_t> data(frame.count() * kStride);
    std::array<std::array<std::uint8_t, 4>, 256> rgba;
    for (int s = 0; s < 256; ++s) rgba[s] = colourOf(scene, std::uint8_t(s));
    for (std::size_t i = 0; i < frame.count(); ++i) {
        std::uint8_t* p = data.data() + i * kStride;
        std::memcpy(p, &frame.positions[3 * i], 12);  // float32 x, y, z, little-endian as the host
        std::memcpy(p + 12, rgba[frame.species[i]].data(), 4);
        p[16] = frame.species[i];
    }
    const auto d = b.CreateVector(data);
    std::vector<Offset<fg::PackedElementField>> fields;
    const auto field = [&](const char* name, std::uint32_t offset, fg::NumericType type) {
        fields.push_back(fg::CreatePackedElementField(b, b.CreateString(name), offset, type));
    };
    field("x", 0, fg::NumericType::FLOAT32);
    field("y", 4, fg::NumericType::FLOAT32);
    field("z", 8, fg::NumericType::FLOAT32);
    field("red", 12, fg::NumericType::UINT8);
    field("green", 13, fg::NumericType::UINT8);
    field("blue", 14, fg::NumericType::UINT8);
    field("alpha", 15, fg::NumericType::UINT8);
    field("species", 16, fg::NumericType::UINT8);
    const auto f = b.CreateVector(fields);
    const auto id = b.CreateString(kFrameBop);
    const auto origin = pose(b, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
    const fg::Time t = stamp(timeNs);
    b.Finish(fg::CreatePointCloud(b, &t, id, origin, kStride, f, d));
    return finish(b);
}

Buffer surfels(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs) {
    FlatBufferBuilder b(1024);
    std::size_t count = 0;
    const bool haveNormals = frame.normals.size() == 3 * frame.count();
    for (std::size_t i = 0; haveNormals && i < frame.count(); ++i) count += isSurface(scene, frame.species[i]);
    const std::size_t every = std::max<std::size_t>(1, (count + kMaxDiscs - 1) / kMaxDiscs);
    // Tables shared by every disc (FlatBuffers lets many parents point at one): the size and the
    // colour of each species.
    const auto size = vec3(b, scene.r0, scene.r0, scene.r0 / 8);
    std::map<std::uint8_t, Offset<fg::Color>> colours;
    std::vector<Offset<fg::CylinderPrimitive>> discs;
    std::size_t k = 0;
    for (std::size_t i = 0; haveNormals && i < frame.count(); ++i) {
        const std::uint8_t species = frame.species[i];
        if (!isSurface(scene, species) || k++ % every != 0) continue;
        const Eigen::Vector3d at(frame.positions[3 * i], frame.positions[3 * i + 1], frame.positions[3 * i + 2]);
        Eigen::Vector3d n(frame.normals[3 * i], frame.normals[3 * i + 1], frame.normals[3 * i + 2]);
        n = n.norm() > 0 ? n.normalized() : Eigen::Vector3d::UnitZ();
        const auto p = pose(b, at, n);
        auto c = colours.find(species);
        if (c == colours.end()) c = colours.emplace(species, colour(b, colourOf(scene, species))).first;
        discs.push_back(fg::CreateCylinderPrimitive(b, p, size, 1.0, 1.0, c->second));
    }
    const auto meta =
        std::vector{fg::CreateKeyValuePair(b, b.CreateString("every"), b.CreateString(std::to_string(every)))};
    const fg::Time t = stamp(timeNs);
    const auto entity = fg::CreateSceneEntityDirect(b, &t, kFrameBop, "surfels", nullptr, false, &meta, nullptr,
                                                    nullptr, nullptr, &discs);
    return sceneUpdate(b, {entity}, {});
}

Buffer probe(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs) {
    FlatBufferBuilder b(512);
    const fg::Time t = stamp(timeNs);
    if (!frame.probeActive)
        return sceneUpdate(
            b, {}, {fg::CreateSceneEntityDeletionDirect(b, &t, fg::SceneEntityDeletionType::MATCHING_ID, "probe")});
    const Eigen::Vector3d& at = frame.probePosition;
    const auto sp = pose(b, at, Eigen::Vector3d::UnitZ());
    const auto size = vec3(b, scene.r0 / 2, scene.r0 / 2, scene.r0 / 2);
    const auto red = colour(b, {230, 40, 40, 220});
    const std::vector spheres{fg::CreateSpherePrimitive(b, sp, size, red)};
    std::vector<Offset<fg::ArrowPrimitive>> arrows;
    const double f = frame.probeForce.norm();
    if (f > 0) {
        // Foxglove's arrows point along their pose's x axis: rotate x onto the force's direction.
        const Eigen::Vector3d dir = frame.probeForce / f;
        const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), dir);
        const auto ap =
            fg::CreatePose(b, vec3(b, at.x(), at.y(), at.z()), fg::CreateQuaternion(b, q.x(), q.y(), q.z(), q.w()));
        const double length = 2 * scene.r0 * f / std::max(1.0, f);
        arrows.push_back(fg::CreateArrowPrimitive(b, ap, 0.75 * length, scene.r0 / 10, 0.25 * length, scene.r0 / 4,
                                                  colour(b, {250, 200, 40, 255})));
    }
    const auto entity =
        fg::CreateSceneEntityDirect(b, &t, kFrameBop, "probe", nullptr, false, nullptr, &arrows, nullptr, &spheres);
    return sceneUpdate(b, {entity}, {});
}

Buffer worldToBop(const SceneInfo& scene, std::uint64_t timeNs) {
    FlatBufferBuilder b(256);
    const Eigen::Vector3d c = -(scene.boxLo + scene.boxHi) / 2;
    const fg::Time t = stamp(timeNs);
    const auto translation = vec3(b, c.x(), c.y(), c.z());
    const auto rotation = fg::CreateQuaternion(b, 0, 0, 0, 1);
    b.Finish(fg::CreateFrameTransformDirect(b, &t, kFrameWorld, kFrameBop, translation, rotation));
    return finish(b);
}

Buffer frameStats(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs) {
    FlatBufferBuilder b(256);
    const fg::Time t = stamp(timeNs);
    const auto& s = frame.stats;
    const auto& f = frame.probeForce;
    const UnitSystem& u = scene.unitSystem;
    b.Finish(bop::plot::CreateFrameStats(
        b, &t, frame.step, frame.simTime, s.kinetic, s.potential, s.kinetic + s.potential, s.pressure, s.stepRateHz,
        frame.probeActive, f.x(), f.y(), f.z(), f.norm(), s.cavityVolume, s.particleCount,
        u.physical ? u.toS(frame.simTime) : 0.0, s.realTimeFactor, u.physical ? u.toN(f.norm()) : 0.0));
    return finish(b);
}

}  // namespace bop::protocol::fox
