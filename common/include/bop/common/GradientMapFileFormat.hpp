#pragma once
// The on-disk pieces of the gradient-map cache file shared by the whole-file reader/writer
// (common/src/GradientMapFile.cpp) and the server's windowed reader (shape/GradientMapFileView.cpp).
// Layout: see GradientMapFile.hpp.
#include "bop/common/GradientMap.hpp"

#include <cstddef>
#include <cstdint>

namespace bop::gmfile {

constexpr char kMagic[8] = {'B', 'O', 'P', 'G', 'M', 'A', 'P', '\0'};
constexpr std::uint32_t kVersion = 2;                     // 2: the bags' parents
constexpr std::size_t kMaxVoxels = std::size_t(1) << 32;  // nearest indices are u32
constexpr std::size_t kFileHeaderBytes = 8 + 4 + 8 + 4;   // magic, version, key, frame count
constexpr std::size_t kParentBytes = 128;                 // u8 parent[128] per frame
constexpr std::size_t kFrameHeaderBytes = 3 * 4 + 3 * 8 + 8 + 8 + 4 + kParentBytes + 8;  // dims .. surface count
constexpr std::uint32_t kMaxFrames = 4096;  // sanity bound on the frame count

// The parents as a file holds them (a nested chain when the map names none) and back; fromParents
// throws std::invalid_argument for a parent that is no bag or a cycle.
void toParents(const GradientMap& m, std::uint8_t (&out)[kParentBytes]);
void fromParents(const std::uint8_t (&in)[kParentBytes], GradientMap& m);

struct SurfaceRecord {  // 36 bytes on disk
    std::uint32_t voxel;
    std::uint8_t species, pad[3];
    float normal[3], meanCurvature, gaussCurvature, kappa, cpWeight;
};
static_assert(sizeof(SurfaceRecord) == 36);

// FNV-1a, 64 bit. Pass the previous result as h to hash a file chunk by chunk.
constexpr std::uint64_t kHashSeed = 1469598103934665603ULL;
inline std::uint64_t hashBytes(const unsigned char* p, std::size_t n, std::uint64_t h = kHashSeed) {
    for (std::size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

}  // namespace bop::gmfile
