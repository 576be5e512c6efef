#pragma once
// The gradient-map cache file (.bopgm): what bop-shape writes so that the server need not
// rebuild a map, and what haptic clients download from it. Little-endian binary, documented in docs/file-formats.md:
//   "BOPGMAP\0", u32 version, u64 key (hash of the scene's shape tables and source files),
//   u32 frames, per frame {i32 nx ny nz, f64 origin_mm[3], f64 voxel_mm, f64 r0_voxels,
//   i32 bags, u8 parent[128] (parent[b]: the bag holding bag b, 0 none; [0] and beyond the bags 0),
//   u64 surface count, u8 occ[N], u32 nearest[N], surface records}, u64 checksum. Version 2; a
//   file of an earlier version is a stale cache.
#include "bop/common/GradientMap.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bop {

std::uint64_t hashText(const std::string& text);  // FNV-1a, 64 bit

// Written atomically (temporary file, fsync, rename).
void writeGradientMaps(const std::string& path, const std::vector<GradientMap>& frames, std::uint64_t key);

// nullopt if the file is absent or was made for another key or an earlier version (a stale cache);
// bop::Error naming the file if it is truncated, corrupt or inconsistent.
std::optional<std::vector<GradientMap>> readGradientMaps(const std::string& path, std::uint64_t key);
// The same from the file's bytes in memory (a haptic client's download); `name` names them in errors.
std::optional<std::vector<GradientMap>> readGradientMaps(std::span<const std::uint8_t> bytes, std::uint64_t key,
                                                         const std::string& name);

}  // namespace bop
