// Compact8 frames (codec/Quantise.hpp): 8 bytes a particle with normals and 6 without, positions
// within the Quantised16 bound, normals within the 8-bit octahedral angle, every particle's id,
// species and position kept together though the chunk groups particles by species, and chunks
// whose runs disagree with their arrays refused.
#include "ProtocolSamples.hpp"
#include "codec/Codec.hpp"
#include "codec/Quantise.hpp"
#include "frame_generated.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

using namespace bop::protocol;
using namespace bop::protocol::samples;

namespace {

double angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

Eigen::Vector3d at(const std::vector<float>& v, std::size_t i) {
    return {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
}

}  // namespace

TEST_CASE("8-bit octahedral normals stay within the stated angle", "[protocol]") {
    std::mt19937 rng(6);
    std::normal_distribution<double> g(0, 1);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
        const auto code = octEncode8(n);
        const Eigen::Vector3d d = octDecode8(code[0], code[1]);
        REQUIRE(std::abs(d.norm() - 1.0) < 1e-12);
        worst = std::max(worst, angle(n, d));
    }
    INFO("worst angle " << worst << " rad, stated " << kOct8MaxAngleRad);
    CHECK(worst <= kOct8MaxAngleRad);
    CHECK(worst >= 0.5 * kOct8MaxAngleRad);  // the statement is not loose
    CHECK(kOct8MaxAngleRad < 0.0167);        // 0.95 degrees
    // A zero normal (volume particles) encodes as +z (within the angle: 255 levels have no exact 0).
    const auto zero = octEncode8(Eigen::Vector3d::Zero());
    CHECK(angle(octDecode8(zero[0], zero[1]), Eigen::Vector3d::UnitZ()) <= kOct8MaxAngleRad);
}

TEST_CASE("compact frames keep each particle's id, species, position and normal together", "[protocol]") {
    StateFrame f = sampleFrame(5000, FrameEncoding::Compact8, true, true);
    std::mt19937 rng(3);
    for (auto& s : f.species) s = std::uint8_t(1 + rng() % 5);  // interleaved species: the codec groups them
    std::map<std::uint64_t, std::size_t> original;
    for (std::size_t i = 0; i < f.count(); ++i) original[f.ids[i]] = i;
    const Eigen::Vector3d bound = positionErrorBound(f.quantLo, f.quantHi);
    const auto chunks = encodeStateFrameChunks(f, 20'000);
    REQUIRE(chunks.size() > 3);
    std::size_t seen = 0;
    for (const Buffer& c : chunks) {
        const auto d = decodeStateFrame(c.data(), c.size());
        REQUIRE(d.ok());
        const StateFrame& g = d.value;
        CHECK(g.encoding == FrameEncoding::Compact8);
        CHECK(std::is_sorted(g.species.begin(), g.species.end()));  // one run per species
        for (std::size_t i = 0; i < g.count(); ++i) {
            const std::size_t k = original.at(g.ids[i]);
            REQUIRE(k >= g.firstIndex);  // the chunk's own particles, regrouped
            REQUIRE(k < g.firstIndex + g.count());
            REQUIRE(g.species[i] == f.species[k]);
            REQUIRE(((at(g.positions, i) - at(f.positions, k)).cwiseAbs().array() <= bound.array()).all());
            REQUIRE(angle(at(g.normals, i), at(f.normals, k)) <= kOct8MaxAngleRad);
        }
        seen += g.count();
    }
    CHECK(seen == f.count());
}

TEST_CASE("compact frames take 8 bytes a particle with normals and 6 without", "[protocol]") {
    const std::size_t n = 100000;
    for (const bool normals : {true, false}) {
        StateFrame f = sampleFrame(n, FrameEncoding::Compact8, normals, false);
        const Buffer compact = encodeStateFrame(f);
        f.encoding = FrameEncoding::Quantised16;
        const Buffer q16 = encodeStateFrame(f);
        f.encoding = FrameEncoding::Float32;
        const Buffer f32 = encodeStateFrame(f);
        const double per = double(compact.size()) / n;
        INFO((normals ? "with" : "without") << " normals, bytes a particle: Compact8 " << per << ", Quantised16 "
                                            << double(q16.size()) / n << ", Float32 " << double(f32.size()) / n);
        CHECK(per <= (normals ? 8.0 : 6.0) + 0.01);  // 4 species runs and the header over 10^5 particles
        CHECK(per >= (normals ? 8.0 : 6.0));
        CHECK(double(q16.size()) / n >= (normals ? 11.0 : 7.0));
    }
}

TEST_CASE("compact chunks whose runs disagree with their arrays are refused", "[protocol]") {
    const StateFrame f = sampleFrame(100, FrameEncoding::Compact8, true, false);
    const auto build = [&](std::vector<std::uint8_t> runSpecies, std::vector<std::uint32_t> runLengths,
                           std::size_t qpositions, bool withSpecies) {
        flatbuffers::FlatBufferBuilder b;
        const auto q = b.CreateVector(std::vector<std::uint16_t>(qpositions, 7));
        const auto rs = b.CreateVector(runSpecies);
        const auto rl = b.CreateVector(runLengths);
        const auto sp = b.CreateVector(std::vector<std::uint8_t>(withSpecies ? 100 : 0, 1));
        const bop::wire::Vec3 lo(f.quantLo.x(), f.quantLo.y(), f.quantLo.z()),
            hi(f.quantHi.x(), f.quantHi.y(), f.quantHi.z());
        bop::wire::StateFrameBuilder s(b);
        s.add_frame_particle_count(100);
        s.add_encoding(bop::wire::FrameEncoding::Compact8);
        s.add_quant_lo(&lo);
        s.add_quant_hi(&hi);
        s.add_qpositions(q);
        s.add_run_species(rs);
        s.add_run_lengths(rl);
        if (withSpecies) s.add_species(sp);
        bop::wire::FinishStateFrameBuffer(b, s.Finish());
        return decodeStateFrame(b.GetBufferPointer(), b.GetSize());
    };
    const auto good = build({1, 2}, {60, 40}, 300, false);
    REQUIRE(good.ok());
    CHECK(good.value.count() == 100);
    CHECK(good.value.species[59] == 1);
    CHECK(good.value.species[60] == 2);
    CHECK(build({1, 2}, {60, 41}, 300, false).message.find("qpositions") != std::string::npos);
    CHECK(build({1}, {60, 40}, 300, false).message.find("run_species") != std::string::npos);
    CHECK(build({1, 2}, {60, 40}, 300, true).message.find("another encoding") != std::string::npos);
    CHECK(build({1, 0}, {60, 40}, 300, false).message.find("species") != std::string::npos);  // species 0 is none
    // Runs as the encoder writes them, or a decode and encode would regroup the particles.
    CHECK(build({2, 1}, {60, 40}, 300, false).message.find("increasing species") != std::string::npos);
    CHECK(build({1, 1}, {60, 40}, 300, false).message.find("increasing species") != std::string::npos);
    CHECK(build({1, 2, 3}, {60, 0, 40}, 300, false).message.find("at least 1 particle") != std::string::npos);
    CHECK_FALSE(build({1, 2}, {0xFFFFFFFFu, 0xFFFFFFFFu}, 300, false).ok());  // a huge run is not allocated
}
