// The Python client decodes what the C++ encoder writes: one frame in each encoding, in chunks,
// read by tests/python/decode_check.py (python/bop/frames.py) and matched particle by particle.
#include "ProtocolSamples.hpp"
#include "TestUtil.hpp"
#include "codec/Codec.hpp"
#include "codec/Quantise.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>
#include <random>
#include <sstream>

using namespace bop::protocol;

TEST_CASE("the Python client decodes Float32, Quantised16 and Compact8 frames within their bounds",
          "[protocol][python]") {
    const bop::test::TempDir dir("python-decode");
    StateFrame f = samples::sampleFrame(4000, FrameEncoding::Float32, true, true);
    std::mt19937 rng(9);
    for (auto& s : f.species) s = std::uint8_t(1 + rng() % 3);
    {
        std::ofstream raw(dir.file("raw.f32"), std::ios::binary);
        for (std::size_t i = 0; i < f.count(); ++i) {
            raw.write(reinterpret_cast<const char*>(&f.positions[3 * i]), 12);
            raw.write(reinterpret_cast<const char*>(&f.normals[3 * i]), 12);
        }
    }
    for (const auto& [encoding, name] :
         {std::pair{FrameEncoding::Float32, "f32.bin"}, std::pair{FrameEncoding::Quantised16, "q16.bin"},
          std::pair{FrameEncoding::Compact8, "c8.bin"}}) {
        f.encoding = encoding;
        std::ofstream out(dir.file(name), std::ios::binary);
        for (const Buffer& c : encodeStateFrameChunks(f, 30'000)) {  // several chunks: the assembler too
            const std::uint32_t n = std::uint32_t(c.size());
            out.write(reinterpret_cast<const char*>(&n), 4);
            out.write(reinterpret_cast<const char*>(c.data()), std::streamsize(c.size()));
        }
    }
    const Eigen::Vector3d b = positionErrorBound(f.quantLo, f.quantHi);
    std::ofstream(dir.file("bounds.txt")) << std::setprecision(17) << b.x() << ' ' << b.y() << ' ' << b.z() << ' '
                                          << kOctMaxAngleRad << ' ' << kOct8MaxAngleRad << '\n';
    const std::string report = dir.file("report.txt");
    const std::string cmd = "/usr/bin/python3 " + bop::test::sourceDir() + "/tests/python/decode_check.py " +
                            dir.file("") + " " + bop::test::sourceDir() + " > " + report + " 2>&1";
    const int rc = std::system(cmd.c_str());
    std::stringstream text;
    text << std::ifstream(report).rdbuf();
    INFO(text.str());
    CHECK(rc == 0);
    CHECK(text.str().find("decode ok") != std::string::npos);
    CHECK(text.str().find("Compact8: 4000 particles") != std::string::npos);
}
