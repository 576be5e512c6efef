// MCAP chunks (https://mcap.dev/spec "Chunk", "Message Index", "Chunk Index"): round trips with
// zstd and without compression, indexes that point at their chunks and messages (and damage to
// them refused), files cut inside chunks, and the size zstd saves.
#include "McapTestUtil.hpp"

#include <algorithm>
#include <filesystem>

using namespace bop::test::mcap;

namespace {

std::uint64_t loadU64(const Bytes& b, std::size_t at) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(b[at + std::size_t(i)]) << (8 * i);
    return v;
}

// Top-level records of a file: (opcode, offset, whole length).
std::vector<std::tuple<std::uint8_t, std::size_t, std::size_t>> records(const Bytes& b) {
    std::vector<std::tuple<std::uint8_t, std::size_t, std::size_t>> out;
    for (std::size_t pos = 8; pos + 9 <= b.size() - 8;) {
        const std::size_t n = 9 + std::size_t(loadU64(b, pos + 1));
        out.emplace_back(b[pos], pos, n);
        pos += n;
    }
    return out;
}

}  // namespace

TEST_CASE("mcap chunked round trip, zstd and uncompressed, with every chunk indexed", "[mcap]") {
    const Session s = makeSession(1000);
    for (const auto compression : {McapCompression::Zstd, McapCompression::None}) {
        INFO("compression '" << mcapCompressionName(compression) << "'");
        const std::string path = tempPath("chunked.mcap");
        writeSession(path, s, {.chunkBytes = 8192, .compression = compression});
        const McapFile f = readMcap(path);
        CHECK(f.schemas == s.schemas);
        CHECK(f.channels == s.channels);
        REQUIRE(f.messages.size() == s.messages.size());
        for (std::size_t i = 0; i < s.messages.size(); ++i) REQUIRE(f.messages[i] == s.messages[i]);
        // About 150 kB of messages in chunks of at least 8 kB: a few dozen chunks, all indexed.
        CHECK(f.chunkCount > 10);
        CHECK(f.chunkCount < 40);
        CHECK(f.indexedChunks == f.chunkCount);
        REQUIRE(f.statistics.has_value());
        CHECK(f.statistics->chunkCount == f.chunkCount);
        CHECK(f.statistics->messageCount == 1000);
        // Every Message record is inside a chunk; one MessageIndex per channel present per chunk.
        std::size_t chunks = 0, indexes = 0;
        for (const auto& [op, pos, n] : records(readAll(path))) {
            CHECK(op != 0x05);
            chunks += op == 0x06;
            indexes += op == 0x07;
        }
        CHECK(chunks == f.chunkCount);
        CHECK(indexes >= 2 * chunks);
        CHECK(indexes <= 3 * chunks);
    }
}

TEST_CASE("mcap zstd chunks make a repetitive session several times smaller", "[mcap]") {
    Session s = makeSession(400);
    for (std::size_t i = 0; i < s.messages.size(); ++i) {  // smooth data, as particle positions are
        s.messages[i].data.resize(2000);
        for (std::size_t k = 0; k < 2000; ++k) s.messages[i].data[k] = std::uint8_t((k / 7 + i) % 32);
    }
    const std::string plain = tempPath("plain.mcap"), packed = tempPath("packed.mcap");
    writeSession(plain, s, kUnchunked);
    writeSession(packed, s);
    const auto a = std::filesystem::file_size(plain), b = std::filesystem::file_size(packed);
    INFO(a << " bytes unchunked, " << b << " bytes in zstd chunks");
    CHECK(b * 5 < a);
    CHECK(readMcap(packed).messages.size() == 400);
}

TEST_CASE("mcap index damage is refused; chunks cut short keep the complete chunks", "[mcap]") {
    const Session s = makeSession(300);
    const std::string path = tempPath("index.mcap");
    writeSession(path, s, {.chunkBytes = 3000, .compression = McapCompression::None});
    const Bytes good = readAll(path);
    REQUIRE_NOTHROW(parseMcap(good, "good.mcap"));
    const auto recs = records(good);

    // A MessageIndex whose first entry points 1 byte past its message.
    const auto mi = std::find_if(recs.begin(), recs.end(), [](const auto& r) { return std::get<0>(r) == 0x07; });
    REQUIRE(mi != recs.end());
    Bytes bad = good;
    bad[std::get<1>(*mi) + 9 + 2 + 4 + 8] ^= 0x01;  // channel u16, array length u32, time u64, offset
    CHECK(strictFails(bad, "do not match the chunk"));
    // A ChunkIndex pointing at the wrong chunk start (its summary CRC is then wrong too: set it to
    // 0, "not computed", so the index check is what refuses it).
    const auto ci = std::find_if(recs.begin(), recs.end(), [](const auto& r) { return std::get<0>(r) == 0x08; });
    REQUIRE(ci != recs.end());
    bad = good;
    bad[std::get<1>(*ci) + 9 + 16] ^= 0x01;
    std::fill(bad.end() - 12, bad.end() - 8, 0);
    CHECK(strictFails(bad, "is not the start of a Chunk"));

    // Cuts: tolerant reading keeps the messages of the chunks that are complete before the cut.
    std::vector<std::pair<std::size_t, std::size_t>> chunkEnds;  // (end offset, messages so far)
    std::size_t messages = 0;
    for (const auto& [op, pos, n] : recs) {
        if (op != 0x06) continue;
        const std::size_t recordsAt = pos + 9 + 8 + 8 + 8 + 4 + 4 + 8;  // compression "" is 4 bytes
        for (std::size_t at = recordsAt; at < pos + n; at += 9 + std::size_t(loadU64(good, at + 1)))
            messages += good[at] == 0x05;
        chunkEnds.emplace_back(pos + n, messages);
    }
    REQUIRE(messages == 300);
    for (std::size_t cut = 0; cut < good.size(); cut += 13) {
        INFO("cut at " << cut);
        const McapFile f =
            parseMcap(Bytes(good.begin(), good.begin() + std::ptrdiff_t(cut)), "c", McapReadMode::Tolerant);
        std::size_t want = 0;
        for (const auto& [end, count] : chunkEnds)
            if (end <= cut) want = count;
        REQUIRE(f.messages.size() == want);
    }
}

TEST_CASE("mcap chunks compressed with lz4, or damaged, are refused with the reason", "[mcap]") {
    const auto file = [](const std::string& compression, const Bytes& stored, std::uint64_t size) {
        Bytes b = kMagic;
        b.push_back(0x01), le(b, 8, 8), str(b, ""), str(b, "");
        Bytes c;
        le(c, 0, 8), le(c, 0, 8), le(c, size, 8), le(c, 0, 4), str(c, compression), le(c, stored.size(), 8);
        c.insert(c.end(), stored.begin(), stored.end());
        b.push_back(0x06), le(b, c.size(), 8), b.insert(b.end(), c.begin(), c.end());
        b.push_back(0x0F), le(b, 4, 8), le(b, 0, 4);
        b.push_back(0x02), le(b, 20, 8), le(b, 0, 20);
        b.insert(b.end(), kMagic.begin(), kMagic.end());
        return b;
    };
    CHECK_NOTHROW(parseMcap(file("", {}, 0), "empty-chunk.mcap"));
    CHECK(strictFails(file("lz4", {1, 2, 3}, 3), "compression 'lz4' is not supported"));
    CHECK(strictFails(file("zstd", {1, 2, 3}, 3), "zstd cannot decompress"));
    CHECK(strictFails(file("", {1, 2, 3}, 1u << 30), "more than the 268435456 bytes"));
    CHECK(strictFails(file("", {0x02, 1, 0, 0, 0, 0, 0, 0, 0, 0}, 10), "only Schema, Channel and Message"));
    CHECK(strictFails(file("", {0x05, 200, 0, 0, 0, 0, 0, 0, 0}, 9), "is cut short"));
}
