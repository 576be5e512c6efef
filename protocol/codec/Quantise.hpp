#pragma once
// 16-bit quantisation of state frames (FrameEncoding::Quantised16).
//
// Positions: each coordinate x in [lo, hi] travels as q = round((x - lo) / (hi - lo) * 65535);
// coordinates outside are clamped first. Decoded, x' = lo + q (hi - lo) / 65535, so
// |x' - x| <= (hi - lo) / 65535 / 2 in exact arithmetic; positionErrorBound() adds the float32
// rounding of the decoded value.
//
// Normals: octahedral mapping (the unit sphere projected on the octahedron |x|+|y|+|z| = 1, the
// lower half folded over the upper), the two square coordinates in [-1, 1] as uint16 each.
// Quantising either coordinate moves it by at most h = 1 / 65535; the map from the square onto
// the octahedron stretches lengths by at most sqrt 3, and the octahedron lies at least 1 / sqrt 3
// from the origin, so the direction turns by at most sqrt2 h x sqrt3 x sqrt3 = 3 sqrt2 h
// = 6.47e-5 rad (0.0037 degrees); kOctMaxAngleRad adds float32 rounding to that.
// A zero or non-finite normal encodes as +z.
//
// Compact8 frames code the same octahedral coordinates in 8 bits each: h = 1 / 255, so a normal
// turns by at most 3 sqrt2 / 255 = 0.0166 rad (0.95 degrees); kOct8MaxAngleRad adds float32
// rounding. Their positions are those of Quantised16.
#include "codec/Messages.hpp"

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>

namespace bop::protocol {

inline constexpr double kQuantLevels = 65535.0;  // largest uint16

// Largest angle between a unit normal and its decoded octahedral code, radians.
inline constexpr double kOctMaxAngleRad = 3.0 * 1.4142135623730951 / kQuantLevels * 1.001 + 1e-6;
inline constexpr double kOct8MaxAngleRad = 3.0 * 1.4142135623730951 / 255.0 * 1.001 + 1e-6;  // 8-bit codes

// One coordinate against [lo, hi] (lo < hi); NaN maps to lo.
std::uint16_t quantiseCoord(double x, double lo, double hi);
double dequantiseCoord(std::uint16_t q, double lo, double hi);

// Per-axis bound on |decoded - original| for float32 positions inside [lo, hi], length.
Eigen::Vector3d positionErrorBound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

// n positions (xyz floats) to 3n codes; returns how many coordinates were clamped into [lo, hi].
std::size_t quantisePositions(const float* xyz, std::size_t n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              std::uint16_t* out);
void dequantisePositions(const std::uint16_t* q, std::size_t n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                         float* xyz);

std::array<std::uint16_t, 2> octEncode(const Eigen::Vector3d& n);
Eigen::Vector3d octDecode(std::uint16_t u, std::uint16_t v);                 // unit length
void octEncodeNormals(const float* xyz, std::size_t n, std::uint16_t* out);  // 2 codes per normal
void octDecodeNormals(const std::uint16_t* q, std::size_t n, float* xyz);
std::array<std::uint8_t, 2> octEncode8(const Eigen::Vector3d& n);
Eigen::Vector3d octDecode8(std::uint8_t u, std::uint8_t v);                  // unit length
void octEncodeNormals8(const float* xyz, std::size_t n, std::uint8_t* out);  // 2 codes per normal
void octDecodeNormals8(const std::uint8_t* q, std::size_t n, float* xyz);

// Payload bytes of one particle in a chunk at most: position, normal (if sent), species, id (if
// sent). Float32: 12 + 12 + 1 + 8 = 33; Quantised16: 6 + 4 + 1 + 8 = 19; Compact8: 6 + 2 + 8 and
// its species runs, 5 bytes a run, counted here as if every particle began one (in practice a
// chunk holds a run per species: 8 bytes a particle with normals, 6 without). Each array adds a
// 4-byte length and up to 7 bytes of padding per chunk on top.
std::size_t bytesPerParticle(FrameEncoding encoding, bool withNormals, bool withIds);

}  // namespace bop::protocol
