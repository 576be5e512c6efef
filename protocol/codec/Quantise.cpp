// Position quantisation and octahedral normals; the error bounds are derived in Quantise.hpp.
#include "codec/Quantise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bop::protocol {

namespace {

// The per-value kernels below are written without Eigen temporaries, lround or early exits so
// that a million-particle frame codes in a few milliseconds (the batch loops vectorise).
// BOP_BATCH_KERNEL builds a batch loop twice on x86-64, for AVX2 and for the baseline, and picks
// one when the program loads; AVX2 codes a frame about twice as fast.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define BOP_BATCH_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define BOP_BATCH_KERNEL
#endif

double signNotZero(double v) {
    return v < 0 ? -1.0 : 1.0;
}

// A code (uint16, or uint8 for Compact8) back to its square coordinate in [-1, 1].
template <class Code>
double fromCode(Code q) {
    constexpr double levels = std::numeric_limits<Code>::max();
    return q * (2.0 / levels) - 1.0;
}

// In float: normals travel as float32 anyway, and the float loop runs four times faster than the
// double one on baseline x86-64. Float rounding moves a code by at most ~0.01 of a step.
float signNotZero(float v) {
    return v < 0 ? -1.0f : 1.0f;
}

template <class Code>
Code toCode(float s) {
    constexpr float levels = std::numeric_limits<Code>::max();
    const float t = std::min(std::max(0.0f, (s + 1.0f) * 0.5f), 1.0f);  // max(0, NaN) = 0
    return Code(std::int32_t(t * levels + 0.5f));
}

template <class Code>
void octEncodeOne(float x, float y, float z, Code* out) {
    // Both halves computed and selected, so the loop has no data-dependent branch.
    const float l1 = std::abs(x) + std::abs(y) + std::abs(z);
    const bool usable = l1 > 0 && l1 <= std::numeric_limits<float>::max();  // else +z
    const float inv = usable ? 1.0f / l1 : 0.0f;
    const float u = x * inv, v = y * inv;  // on the octahedron
    // The lower half folded over the upper: mirrored across the edges |u| + |v| = 1.
    const float fu = (1.0f - std::abs(v)) * signNotZero(u), fv = (1.0f - std::abs(u)) * signNotZero(v);
    const bool lower = usable && z < 0;
    out[0] = toCode<Code>(lower ? fu : u);
    out[1] = toCode<Code>(lower ? fv : v);
}

template <class Code>
void octDecodeOne(Code qu, Code qv, double* p) {
    double u = fromCode(qu), v = fromCode(qv);
    const double z = 1.0 - std::abs(u) - std::abs(v);
    if (z < 0) {
        const double fu = (1.0 - std::abs(v)) * signNotZero(u);
        v = (1.0 - std::abs(u)) * signNotZero(v);
        u = fu;
    }
    const double inv = 1.0 / std::sqrt(u * u + v * v + z * z);  // >= 1/sqrt3 on the octahedron, never zero
    p[0] = u * inv;
    p[1] = v * inv;
    p[2] = z * inv;
}

}  // namespace

std::uint16_t quantiseCoord(double x, double lo, double hi) {
    double t = (x - lo) / (hi - lo);
    if (!(t > 0)) t = 0;  // also NaN
    if (t > 1) t = 1;
    return std::uint16_t(std::lround(t * kQuantLevels));
}

double dequantiseCoord(std::uint16_t q, double lo, double hi) {
    return lo + (hi - lo) * (q / kQuantLevels);
}

Eigen::Vector3d positionErrorBound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    // Half a quantisation step, plus the float32 rounding of the decoded value (at most eps x).
    const double floatEps = std::numeric_limits<float>::epsilon();
    const Eigen::Vector3d magnitude = lo.cwiseAbs().cwiseMax(hi.cwiseAbs());
    return (hi - lo) / kQuantLevels / 2.0 + magnitude * floatEps;
}

BOP_BATCH_KERNEL std::size_t quantisePositions(const float* xyz, std::size_t n, const Eigen::Vector3d& lo,
                                               const Eigen::Vector3d& hi, std::uint16_t* out) {
    // quantiseCoord() per value, with the division by the range hoisted out of the loop.
    std::size_t clamped = 0;
    const double l[3] = {lo.x(), lo.y(), lo.z()}, h[3] = {hi.x(), hi.y(), hi.z()};
    double scale[3];
    for (int a = 0; a < 3; ++a) scale[a] = kQuantLevels / (h[a] - l[a]);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double x = xyz[3 * i + a];
            const double t = std::min(std::max(0.0, (x - l[a]) * scale[a]), kQuantLevels);  // max(0, NaN) = 0
            clamped += !(x >= l[a] && x <= h[a]);
            out[3 * i + a] = std::uint16_t(t + 0.5);  // t >= 0: rounds half up, as lround
        }
    return clamped;
}

BOP_BATCH_KERNEL void dequantisePositions(const std::uint16_t* q, std::size_t n, const Eigen::Vector3d& lo,
                                          const Eigen::Vector3d& hi, float* xyz) {
    const double l[3] = {lo.x(), lo.y(), lo.z()};
    double step[3];
    for (int a = 0; a < 3; ++a) step[a] = (hi[a] - lo[a]) / kQuantLevels;
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(l[a] + step[a] * q[3 * i + a]);
}

namespace {

// One normal to its code and back; and the batch loops, inlined into each public kernel (and so
// into each of its target clones). Code: uint16 (Quantised16) or uint8 (Compact8).
template <class Code>
std::array<Code, 2> encodeOne(const Eigen::Vector3d& n) {
    std::array<Code, 2> c;
    octEncodeOne(float(n.x()), float(n.y()), float(n.z()), c.data());
    return c;
}

template <class Code>
Eigen::Vector3d decodeOne(Code qu, Code qv) {
    Eigen::Vector3d p;
    octDecodeOne(qu, qv, p.data());
    return p;
}

template <class Code>
inline void encodeBatch(const float* xyz, std::size_t n, Code* out) {
    for (std::size_t i = 0; i < n; ++i) octEncodeOne(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], out + 2 * i);
}

template <class Code>
inline void decodeBatch(const Code* q, std::size_t n, float* xyz) {
    for (std::size_t i = 0; i < n; ++i) {
        double p[3];
        octDecodeOne(q[2 * i], q[2 * i + 1], p);
        for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(p[a]);
    }
}

}  // namespace

std::array<std::uint16_t, 2> octEncode(const Eigen::Vector3d& n) {
    return encodeOne<std::uint16_t>(n);
}
Eigen::Vector3d octDecode(std::uint16_t qu, std::uint16_t qv) {
    return decodeOne(qu, qv);
}
std::array<std::uint8_t, 2> octEncode8(const Eigen::Vector3d& n) {
    return encodeOne<std::uint8_t>(n);
}
Eigen::Vector3d octDecode8(std::uint8_t qu, std::uint8_t qv) {
    return decodeOne(qu, qv);
}

BOP_BATCH_KERNEL void octEncodeNormals(const float* xyz, std::size_t n, std::uint16_t* out) {
    encodeBatch(xyz, n, out);
}
BOP_BATCH_KERNEL void octDecodeNormals(const std::uint16_t* q, std::size_t n, float* xyz) {
    decodeBatch(q, n, xyz);
}
BOP_BATCH_KERNEL void octEncodeNormals8(const float* xyz, std::size_t n, std::uint8_t* out) {
    encodeBatch(xyz, n, out);
}
BOP_BATCH_KERNEL void octDecodeNormals8(const std::uint8_t* q, std::size_t n, float* xyz) {
    decodeBatch(q, n, xyz);
}

std::size_t bytesPerParticle(FrameEncoding encoding, bool withNormals, bool withIds) {
    const bool q16 = encoding == FrameEncoding::Quantised16, c8 = encoding == FrameEncoding::Compact8;
    const std::size_t position = q16 || c8 ? 3 * sizeof(std::uint16_t) : 3 * sizeof(float);
    const std::size_t normal = !withNormals ? 0 : c8 ? 2 : q16 ? 2 * sizeof(std::uint16_t) : 3 * sizeof(float);
    const std::size_t id = withIds ? sizeof(std::uint64_t) : 0;
    const std::size_t species =
        c8 ? sizeof(std::uint8_t) + sizeof(std::uint32_t) : sizeof(std::uint8_t);  // a run each, at worst
    return position + normal + species + id;
}

}  // namespace bop::protocol
