#pragma once
// Shared by the MCAP tests (TestMcap.cpp, TestMcapDamage.cpp): temporary files, byte helpers for
// spelling out the format by hand, and a generated session with its expected content.
#include "TestUtil.hpp"
#include "bop/common/Error.hpp"
#include "recording/McapReader.hpp"
#include "recording/McapWriter.hpp"

#include <catch2/catch.hpp>
#include <zlib.h>

#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace bop::test::mcap {

using namespace bop::recording;
using Bytes = std::vector<std::uint8_t>;

inline std::string tempPath(const std::string& name) {
    static const bop::test::TempDir dir("mcap");
    return dir.file(name);
}

inline Bytes readAll(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

// Little-endian appends, for spelling out expected bytes by hand (n > 8 pads with zero bytes).
inline void le(Bytes& b, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) b.push_back(i < 8 ? std::uint8_t(v >> (8 * i)) : 0);
}
inline void str(Bytes& b, const std::string& s) {
    le(b, s.size(), 4);
    b.insert(b.end(), s.begin(), s.end());
}
inline const Bytes kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline std::uint32_t crcOf(const Bytes& b, std::size_t from, std::size_t to) {
    return std::uint32_t(crc32(0, b.data() + from, uInt(to - from)));
}

struct Session {
    std::vector<McapSchema> schemas;
    std::vector<McapChannel> channels;
    std::vector<McapMessage> messages;
};

// 2 schemas, 3 channels, n messages: random sizes (0 bytes, one of 70 kB), log times in ns that
// mostly rise but sometimes step back, publish times before them, per-channel sequence numbers.
inline Session makeSession(int n) {
    Session s;
    s.schemas = {{1, "bop.Frame", "flatbuffer", {0x18, 0, 0, 0, 'B', 'F', 'B', 'S', 0x89, 'M', 'C', 'A', 'P', 0}},
                 {2, "bop.Command", "flatbuffer", {}}};
    s.channels = {{1, 1, "/frames", "flatbuffer", {{"rate_hz", "1000"}, {"units", "SI"}}},
                  {2, 1, "/frames/low", "flatbuffer", {}},
                  {3, 2, "/commands", "flatbuffer", {{"source", "haptic_client"}}}};
    std::mt19937_64 rng(12345);
    std::uint32_t seq[4] = {};
    for (int i = 0; i < n; ++i) {
        McapMessage m;
        m.channelId = std::uint16_t(i % 7 == 0 ? 3 : 1 + i % 2);
        m.sequence = seq[m.channelId]++;
        m.logTimeNs = 1'700'000'000'000'000'000ull + std::uint64_t(i) * 1'000'000 + rng() % 900'000 -
                      (i % 50 == 49 ? 5'000'000 : 0);
        m.publishTimeNs = m.logTimeNs - rng() % 100'000;
        m.data.resize(i == 0 ? 0 : i == n / 2 ? 70'000 : rng() % 300);
        for (auto& byte : m.data) byte = std::uint8_t(rng());
        if (i == 10) m.data.assign({'P', 'A', 'Y', 'L', 'O', 'A', 'D', '-', 'M', 'A', 'R', 'K'});
        s.messages.push_back(std::move(m));
    }
    return s;
}

// Every Message record on its own in the data section, as the byte-level tests expect.
inline const McapWriterOptions kUnchunked{.chunkBytes = 0};

inline void writeSession(const std::string& path, const Session& s, const McapWriterOptions& options = {}) {
    McapWriter w(path, "", options);
    for (const auto& x : s.schemas) REQUIRE(w.addSchema(x.name, x.encoding, x.data) == x.id);
    for (const auto& c : s.channels) REQUIRE(w.addChannel(c.schemaId, c.topic, c.messageEncoding, c.metadata) == c.id);
    for (const auto& m : s.messages) w.write(m.channelId, m.sequence, m.logTimeNs, m.publishTimeNs, m.data);
    w.close();
}

// End offsets of the Message records of an unchunked file, found by walking <opcode u8><length
// u64> records directly.
inline std::vector<std::size_t> messageEnds(const Bytes& b) {
    std::vector<std::size_t> ends;
    for (std::size_t pos = 8; b[pos] != 0x02;) {
        std::uint64_t len = 0;
        for (int i = 0; i < 8; ++i) len |= std::uint64_t(b[pos + 1 + i]) << (8 * i);
        const std::size_t end = pos + 9 + std::size_t(len);
        if (b[pos] == 0x05) ends.push_back(end);
        pos = end;
    }
    return ends;
}

inline bool strictFails(const Bytes& b, const std::string& contains = "") {
    try {
        parseMcap(b, "cut.mcap");
    } catch (const bop::Error& e) {
        return std::string(e.what()).find(contains) != std::string::npos;
    }
    return false;
}

}  // namespace bop::test::mcap
