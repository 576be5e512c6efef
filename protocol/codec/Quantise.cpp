// Position quantisation and octahedral normals; the error bounds are derived in Quantise.hpp.
#include "codec/Quantise.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bop::protocol {

namespace {

double signNotZero(double v) {
    return v < 0 ? -1.0 : 1.0;
}

// Square coordinate in [-1, 1] to uint16 and back.
std::uint16_t toCode(double s) {
    const double t = std::clamp((s + 1.0) * 0.5, 0.0, 1.0);
    return std::uint16_t(std::lround(t * kQuantLevels));
}
double fromCode(std::uint16_t q) {
    return q / kQuantLevels * 2.0 - 1.0;
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

std::size_t quantisePositions(const float* xyz, std::size_t n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                              std::uint16_t* out) {
    // quantiseCoord() per value, with the division by the range hoisted out of the loop (a 1M
    // particle frame is quantised many times a second).
    std::size_t clamped = 0;
    const Eigen::Vector3d scale = Eigen::Vector3d::Constant(kQuantLevels).cwiseQuotient(hi - lo);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double x = xyz[3 * i + a];
            double t = (x - lo[a]) * scale[a];
            if (!(t > 0)) t = 0;  // also NaN
            if (t > kQuantLevels) t = kQuantLevels;
            clamped += !(x >= lo[a] && x <= hi[a]);
            out[3 * i + a] = std::uint16_t(t + 0.5);  // t >= 0: rounds half up, as lround
        }
    return clamped;
}

void dequantisePositions(const std::uint16_t* q, std::size_t n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                         float* xyz) {
    const Eigen::Vector3d step = (hi - lo) / kQuantLevels;
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(lo[a] + step[a] * q[3 * i + a]);
}

std::array<std::uint16_t, 2> octEncode(const Eigen::Vector3d& n) {
    const double l1 = n.cwiseAbs().sum();
    if (!(l1 > 0) || !std::isfinite(l1)) return {toCode(0.0), toCode(0.0)};  // +z
    const Eigen::Vector3d p = n / l1;                                        // on the octahedron
    double u = p.x(), v = p.y();
    if (p.z() < 0) {  // fold the lower half over the upper: mirror across the edges |u|+|v| = 1
        u = (1.0 - std::abs(p.y())) * signNotZero(p.x());
        v = (1.0 - std::abs(p.x())) * signNotZero(p.y());
    }
    return {toCode(u), toCode(v)};
}

Eigen::Vector3d octDecode(std::uint16_t qu, std::uint16_t qv) {
    const double u = fromCode(qu), v = fromCode(qv);
    const double z = 1.0 - std::abs(u) - std::abs(v);
    Eigen::Vector3d p(u, v, z);
    if (z < 0) {
        p.x() = (1.0 - std::abs(v)) * signNotZero(u);
        p.y() = (1.0 - std::abs(u)) * signNotZero(v);
    }
    return p.normalized();  // |p| >= 1/sqrt3 on the octahedron, so never zero
}

void octEncodeNormals(const float* xyz, std::size_t n, std::uint16_t* out) {
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = octEncode(Eigen::Vector3d(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]));
        out[2 * i] = c[0];
        out[2 * i + 1] = c[1];
    }
}

void octDecodeNormals(const std::uint16_t* q, std::size_t n, float* xyz) {
    for (std::size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d d = octDecode(q[2 * i], q[2 * i + 1]);
        for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(d[a]);
    }
}

std::size_t bytesPerParticle(FrameEncoding encoding, bool withNormals, bool withIds) {
    const bool q = encoding == FrameEncoding::Quantised16;
    const std::size_t position = q ? 3 * sizeof(std::uint16_t) : 3 * sizeof(float);
    const std::size_t normal = withNormals ? (q ? 2 * sizeof(std::uint16_t) : 3 * sizeof(float)) : 0;
    const std::size_t id = withIds ? sizeof(std::uint64_t) : 0;
    return position + normal + sizeof(std::uint8_t) + id;
}

}  // namespace bop::protocol
