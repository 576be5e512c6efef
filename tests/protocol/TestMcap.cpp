// MCAP recording: round trip of a session, byte layout against the spec (https://mcap.dev/spec),
// CRCs, and an independent parse by tests/protocol/mcap_check.py when python3 is available.
#include "McapTestUtil.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <tuple>

using namespace bop::test::mcap;

TEST_CASE("mcap round trip of 2 schemas, 3 channels and 1000 messages", "[mcap]") {
    const std::string path = tempPath("session.mcap");
    const Session s = makeSession(1000);
    writeSession(path, s, kUnchunked);
    CHECK(std::filesystem::exists(path));
    CHECK_FALSE(std::filesystem::exists(path + ".partial"));

    const McapFile f = readMcap(path);
    CHECK(f.profile.empty());
    CHECK(f.library == "bop");
    CHECK(f.schemas == s.schemas);
    CHECK(f.channels == s.channels);
    REQUIRE(f.messages.size() == s.messages.size());
    for (std::size_t i = 0; i < s.messages.size(); ++i) REQUIRE(f.messages[i] == s.messages[i]);
    CHECK(f.complete);
    CHECK(f.hasDataEnd);
    CHECK(f.dataSectionCrc != 0);

    McapStatistics want;
    want.messageCount = 1000;
    want.schemaCount = 2;
    want.channelCount = 3;
    want.messageStartTimeNs = want.messageEndTimeNs = s.messages[0].logTimeNs;
    for (const auto& m : s.messages) {
        want.messageStartTimeNs = std::min(want.messageStartTimeNs, m.logTimeNs);
        want.messageEndTimeNs = std::max(want.messageEndTimeNs, m.logTimeNs);
        ++want.channelMessageCounts[m.channelId];
    }
    REQUIRE(f.statistics.has_value());
    CHECK(*f.statistics == want);
    CHECK(want.channelMessageCounts.at(3) == 143);

    if (std::system("python3 -c 'import struct, zlib' > /dev/null 2>&1") != 0) {
        WARN("python3 not found: the independent format check in tests/protocol/mcap_check.py is skipped");
        return;
    }
    const std::string report = tempPath("check.txt");
    const std::string cmd =
        "python3 " + bop::test::sourceDir() + "/tests/protocol/mcap_check.py " + path + " > " + report;
    REQUIRE(std::system(cmd.c_str()) == 0);
    std::stringstream text;
    text << std::ifstream(report).rdbuf();
    const std::string out = text.str();
    INFO(out);
    CHECK(out.find("header profile='' library='bop'") != std::string::npos);
    CHECK(out.find("data_crc ok") != std::string::npos);
    CHECK(out.find("summary_crc ok") != std::string::npos);
    CHECK(out.find("records 1=1 2=1 3=4 4=6 5=1000 11=1 14=3 15=1") != std::string::npos);
    CHECK(out.find("statistics messages=1000 schemas=2 channels=3 start=" + std::to_string(want.messageStartTimeNs) +
                   " end=" + std::to_string(want.messageEndTimeNs)) != std::string::npos);
    CHECK(out.find("topics /frames,/frames/low,/commands") != std::string::npos);
}

TEST_CASE("mcap bytes of a small file match the spec layout", "[mcap]") {
    const std::string path = tempPath("small.mcap");
    {
        McapWriter w(path, "", kUnchunked);
        REQUIRE(w.addSchema("s", "flatbuffer", Bytes{0xAA}) == 1);
        REQUIRE(w.addChannel(1, "/t", "flatbuffer", {{"k", "v"}}) == 1);
        w.write(1, 7, 0x0102030405060708ull, 9, Bytes{1, 2, 3});
        w.close();
    }
    Bytes want = kMagic;
    // Header (op 0x01): profile "" and library "bop" -> content 4 + 0 + 4 + 3 = 11 bytes.
    Bytes header = {0x01, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 'b', 'o', 'p'};
    want.insert(want.end(), header.begin(), header.end());
    // Schema (0x03): id u16, name, encoding, u32-prefixed data -> 2 + 5 + 14 + 5 = 26 bytes.
    want.push_back(0x03), le(want, 26, 8), le(want, 1, 2), str(want, "s"), str(want, "flatbuffer");
    le(want, 1, 4), want.push_back(0xAA);
    // Channel (0x04): id, schema id, topic, encoding, map {"k": "v"} of 14 bytes -> 38 bytes.
    want.push_back(0x04), le(want, 38, 8), le(want, 1, 2), le(want, 1, 2), str(want, "/t"), str(want, "flatbuffer");
    le(want, 10, 4), str(want, "k"), str(want, "v");
    // Message (0x05): channel u16, sequence u32, log time u64, publish time u64, data to the end.
    want.push_back(0x05), le(want, 25, 8), le(want, 1, 2), le(want, 7, 4), le(want, 0x0102030405060708ull, 8);
    le(want, 9, 8), want.insert(want.end(), {1, 2, 3});
    const std::size_t dataEnd = want.size();
    want.push_back(0x0F), le(want, 4, 8), le(want, crcOf(want, 0, dataEnd), 4);  // CRC from byte 0

    const Bytes got = readAll(path);
    REQUIRE(got.size() > want.size());
    CHECK(Bytes(got.begin(), got.begin() + std::ptrdiff_t(want.size())) == want);
    // Summary: copies of the Schema (35 bytes at 28) and Channel (47 bytes at 63) records, then
    // Statistics; one SummaryOffset per group; Footer; magic.
    const std::size_t schemaCopy = want.size(), channelCopy = schemaCopy + 35, stats = channelCopy + 47;
    const auto at = [&](std::size_t from, std::size_t n) {
        return Bytes(got.begin() + std::ptrdiff_t(from), got.begin() + std::ptrdiff_t(from + n));
    };
    CHECK(at(schemaCopy, 35) == at(28, 35));
    CHECK(at(channelCopy, 47) == at(63, 47));
    // Statistics (0x0B): counts 1 message, 1 schema, 1 channel, 0 attachments/metadata/chunks, start
    // and end log time, map {channel 1: 1 message} of 10 bytes -> 8+2+4+3*4+8+8+4+10 = 56 bytes.
    Bytes tail;
    tail.push_back(0x0B), le(tail, 56, 8), le(tail, 1, 8), le(tail, 1, 2), le(tail, 1, 4), le(tail, 0, 12);
    le(tail, 0x0102030405060708ull, 8), le(tail, 0x0102030405060708ull, 8), le(tail, 10, 4), le(tail, 1, 2);
    le(tail, 1, 8);
    const std::size_t offsets = stats + tail.size();
    using Group = std::tuple<int, std::size_t, int>;  // opcode, start, length of the group
    for (auto [op, start, len] : {Group{3, schemaCopy, 35}, Group{4, channelCopy, 47}, Group{11, stats, 65}}) {
        tail.push_back(0x0E), le(tail, 17, 8), tail.push_back(std::uint8_t(op)), le(tail, start, 8), le(tail, len, 8);
    }
    tail.push_back(0x02), le(tail, 20, 8), le(tail, schemaCopy, 8), le(tail, offsets, 8);
    REQUIRE(got.size() == stats + tail.size() + 4 + 8);
    CHECK(at(stats, tail.size()) == tail);
    // summary_crc: from the summary start through the Footer's summary_offset_start field.
    Bytes crc;
    le(crc, crcOf(got, schemaCopy, got.size() - 12), 4);
    CHECK(at(got.size() - 12, 4) == crc);
    CHECK(at(got.size() - 8, 8) == kMagic);
}

TEST_CASE("mcap CRC mismatches are detected", "[mcap]") {
    const std::string path = tempPath("crc.mcap");
    writeSession(path, makeSession(200), kUnchunked);
    const Bytes good = readAll(path);
    const std::string marker = "PAYLOAD-MARK";
    const auto it = std::search(good.begin(), good.end(), marker.begin(), marker.end());
    REQUIRE(it != good.end());
    Bytes bad = good;
    bad[std::size_t(it - good.begin()) + 3] ^= 0x01;
    CHECK(strictFails(bad, "data section CRC mismatch"));
    CHECK_THROWS_AS(parseMcap(bad, "crc.mcap", McapReadMode::Tolerant), bop::Error);

    // The Statistics record's message_start_time, found through the Footer and SummaryOffset records.
    const std::size_t footer = good.size() - 8 - 29;
    std::size_t offsets = 0, stats = 0;
    for (int i = 0; i < 8; ++i) offsets |= std::size_t(good[footer + 17 + i]) << (8 * i);
    for (std::size_t p = offsets; p < footer; p += 26)
        if (good[p + 9] == 0x0B)
            for (int i = 0; i < 8; ++i) stats |= std::size_t(good[p + 10 + i]) << (8 * i);
    REQUIRE(good[stats] == 0x0B);
    bad = good;
    bad[stats + 9 + 26] ^= 0x40;
    CHECK(strictFails(bad, "summary CRC mismatch"));
    CHECK_NOTHROW(parseMcap(good, "crc.mcap"));
}
