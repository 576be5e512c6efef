#pragma once
// BoP state seen through Foxglove's well-known schemas (schemas/foxglove/foxglove_types.fbs),
// encoded in FlatBuffers as Foxglove decodes them. One whole frame (FrameAssembler's output) at a
// time; every message is stamped with the wall time it was recorded at. Frames: particles live in
// kFrameBop, whose origin sits at minus the box centre in kFrameWorld (so the box is centred at
// the world's origin); lengths stay in simulation units.
#include "codec/Codec.hpp"

#include <cstdint>

namespace bop::protocol::fox {

inline constexpr const char* kFrameWorld = "world";
inline constexpr const char* kFrameBop = "bop";
// Largest number of surfel discs one SceneUpdate holds; a frame with more surface particles shows
// every k-th (k the smallest that fits), and its entity's metadata says which k.
inline constexpr std::size_t kMaxDiscs = 20000;

// foxglove.PointCloud of every particle: x, y, z (FLOAT32, length), red, green, blue, alpha (UINT8,
// the species colour of the scene) and species (UINT8, 1-based), 17 bytes a point.
Buffer pointCloud(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs);

// foxglove.SceneUpdate with entity "surfels": one disc per surface particle (a cylinder r0 across
// and r0 / 8 thick along its normal), in its species colour.
Buffer surfels(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs);

// foxglove.SceneUpdate with entity "probe": a sphere r0 / 2 across at the probe while it is active
// and an arrow along the force on it (length |F| / max(1, |F|) x 2 r0); deletes the entity while
// the probe is inactive.
Buffer probe(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs);

// foxglove.FrameTransform from kFrameWorld to kFrameBop.
Buffer worldToBop(const SceneInfo& scene, std::uint64_t timeNs);

// bop.plot.FrameStats (schemas/foxglove/frame_stats.fbs): energies, pressure, probe force.
Buffer frameStats(const StateFrame& frame, const SceneInfo& scene, std::uint64_t timeNs);

}  // namespace bop::protocol::fox
