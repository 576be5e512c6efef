// Position quantisation and octahedral normals against the bounds stated in Quantise.hpp, and
// the bytes per particle of each frame encoding.
#include "ProtocolSamples.hpp"
#include "codec/Quantise.hpp"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace bop::protocol;
using namespace bop::protocol::samples;

namespace {

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

TEST_CASE("quantised positions stay within half a step of the original", "[protocol]") {
    const Eigen::Vector3d lo(-20, 0, -1000), hi(30, 5, 1000);
    const Eigen::Vector3d bound = positionErrorBound(lo, hi);
    const Eigen::Vector3d halfStep = (hi - lo) / 65535.0 / 2.0;
    CHECK(bound.x() == Approx(halfStep.x()).epsilon(0.01));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    const std::size_t n = 50000;
    std::vector<float> xyz(3 * n), back(3 * n);
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) xyz[3 * i + a] = float(lo[a] + u(rng) * (hi[a] - lo[a]));
    xyz[0] = float(lo.x());  // the corners are exact
    xyz[1] = float(hi.y());
    std::vector<std::uint16_t> q(3 * n);
    CHECK(quantisePositions(xyz.data(), n, lo, hi, q.data()) == 0);
    dequantisePositions(q.data(), n, lo, hi, back.data());
    CHECK(q[0] == 0);
    CHECK(q[1] == 65535);
    CHECK(back[0] == float(lo.x()));
    CHECK(back[1] == float(hi.y()));
    Eigen::Vector3d worst = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < 3 * n; ++i)
        worst[int(i % 3)] = std::max(worst[int(i % 3)], std::abs(double(back[i]) - double(xyz[i])));
    for (int a = 0; a < 3; ++a) {
        INFO("axis " << a << ": worst " << worst[a] << ", bound " << bound[a]);
        CHECK(worst[a] <= bound[a]);
        CHECK(worst[a] >= 0.9 * halfStep[a]);  // the errors do reach the bound
    }
}

TEST_CASE("positions outside the bounds are clamped and counted", "[protocol]") {
    const Eigen::Vector3d lo(0, 0, 0), hi(10, 10, 10);
    const float xyz[6] = {-1.0f, 5.0f, 11.0f, 10.0f, 0.0f, NAN};
    std::uint16_t q[6];
    CHECK(quantisePositions(xyz, 2, lo, hi, q) == 3);  // -1, 11 and NaN
    CHECK(q[0] == 0);
    CHECK(q[2] == 65535);
    CHECK(q[3] == 65535);
    CHECK(q[5] == 0);
    CHECK(dequantiseCoord(q[1], 0, 10) == Approx(5.0).margin(10.0 / 65535 / 2));
}

TEST_CASE("octahedral normals stay within the stated angle", "[protocol]") {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0, 1);
    std::vector<Eigen::Vector3d> normals;
    for (int i = 0; i < 200000; ++i) normals.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
    // Axes, face centres (where the octahedron is nearest the origin) and the folded lower half.
    for (int sx : {-1, 1})
        for (int sy : {-1, 1})
            for (int sz : {-1, 1}) {
                normals.push_back(Eigen::Vector3d(sx, sy, sz).normalized());
                normals.push_back(Eigen::Vector3d(sx, 0, 0) * sy);
                normals.push_back(Eigen::Vector3d(0, 0, sz));
                normals.push_back(Eigen::Vector3d(sx, sy * 1e-9, sz * 1e-9).normalized());
            }
    double worst = 0;
    for (const Eigen::Vector3d& n : normals) {
        const auto code = octEncode(n);
        const Eigen::Vector3d d = octDecode(code[0], code[1]);
        CHECK(std::abs(d.norm() - 1.0) < 1e-12);
        worst = std::max(worst, angle(n, d));
    }
    INFO("worst angle " << worst << " rad, stated " << kOctMaxAngleRad);
    CHECK(worst <= kOctMaxAngleRad);
    CHECK(worst >= 0.5 * kOctMaxAngleRad);  // the statement is not loose
    CHECK(kOctMaxAngleRad < 7e-5);          // 0.004 degrees

    // Codes are stable: decoding and encoding again gives the same code.
    for (std::uint32_t u = 0; u <= 65535; u += 257)
        for (std::uint32_t v = 0; v <= 65535; v += 263) {
            const auto code = octEncode(octDecode(std::uint16_t(u), std::uint16_t(v)));
            const Eigen::Vector3d a = octDecode(std::uint16_t(u), std::uint16_t(v)), b = octDecode(code[0], code[1]);
            CHECK(angle(a, b) < 1e-9);
        }
    // A zero normal (volume particles) encodes as +z.
    const auto zero = octEncode(Eigen::Vector3d::Zero());
    CHECK(octDecode(zero[0], zero[1]).z() == Approx(1.0));
}

TEST_CASE("bytes per particle of each encoding match the encoded frames", "[protocol]") {
    CHECK(bytesPerParticle(FrameEncoding::Float32, true, false) == 25);
    CHECK(bytesPerParticle(FrameEncoding::Float32, true, true) == 33);
    CHECK(bytesPerParticle(FrameEncoding::Quantised16, true, false) == 11);
    CHECK(bytesPerParticle(FrameEncoding::Quantised16, true, true) == 19);
    CHECK(bytesPerParticle(FrameEncoding::Quantised16, false, false) == 7);
    const std::size_t n = 10000;
    for (const FrameEncoding enc : {FrameEncoding::Float32, FrameEncoding::Quantised16})
        for (const bool normals : {false, true})
            for (const bool ids : {false, true}) {
                const Buffer b = encodeStateFrame(sampleFrame(n, enc, normals, ids));
                const std::size_t payload = n * bytesPerParticle(enc, normals, ids);
                INFO("encoding " << int(enc) << " normals " << normals << " ids " << ids << ": " << b.size()
                                 << " bytes for " << n << " particles");
                CHECK(b.size() >= payload);
                CHECK(b.size() <= payload + 512);  // header, stats, array lengths, padding
            }
}
