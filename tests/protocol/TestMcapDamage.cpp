// MCAP recording under damage: files cut at every byte (strict reading refuses them, tolerant
// reading keeps exactly the complete messages), unfinished recordings, malformed and random input,
// and error messages that name the file.
#include "McapTestUtil.hpp"

#include <algorithm>
#include <filesystem>

using namespace bop::test::mcap;

TEST_CASE("mcap files cut at every byte: strict rejects, tolerant keeps complete messages", "[mcap]") {
    const std::string path = tempPath("cut.mcap");
    Session s = makeSession(41);
    s.messages[20].data.resize(50);  // keep the file small enough to try every cut point
    writeSession(path, s, kUnchunked);
    const Bytes full = readAll(path);
    const std::vector<std::size_t> ends = messageEnds(full);
    REQUIRE(ends.size() == 41);
    for (std::size_t cut = 0; cut < full.size(); ++cut) {
        const Bytes part(full.begin(), full.begin() + std::ptrdiff_t(cut));
        INFO("cut at " << cut << " of " << full.size());
        REQUIRE(strictFails(part));
        const McapFile f = parseMcap(part, "cut.mcap", McapReadMode::Tolerant);
        const auto complete = std::size_t(std::upper_bound(ends.begin(), ends.end(), cut) - ends.begin());
        REQUIRE(f.messages.size() == complete);
        REQUIRE(std::equal(f.messages.begin(), f.messages.end(), s.messages.begin()));
        REQUIRE(f.validBytes <= cut);
        REQUIRE_FALSE(f.complete);
    }
    CHECK(parseMcap(full, "cut.mcap", McapReadMode::Tolerant).complete);
}

TEST_CASE("mcap partial file of an unfinished recording is readable in tolerant mode", "[mcap]") {
    const std::string path = tempPath("unfinished.mcap");
    const Session s = makeSession(1000);
    {
        McapWriter w(path);
        for (const auto& x : s.schemas) w.addSchema(x.name, x.encoding, x.data);
        for (const auto& c : s.channels) w.addChannel(c.schemaId, c.topic, c.messageEncoding, c.metadata);
        for (int i = 0; i < 600; ++i) {
            const auto& m = s.messages[std::size_t(i)];
            w.write(m.channelId, m.sequence, m.logTimeNs, m.publishTimeNs, m.data);
        }
        w.flush();
        CHECK(parseMcap(readAll(w.partialPath()), "p", McapReadMode::Tolerant).messages.size() == 600);
        CHECK_THROWS_AS(readMcap(w.partialPath()), bop::Error);
    }  // destroyed without close(): stays .partial
    CHECK_FALSE(std::filesystem::exists(path));
    const McapFile f = readMcap(path + ".partial", McapReadMode::Tolerant);
    CHECK_FALSE(f.complete);
    REQUIRE(f.messages.size() == 600);
    CHECK(f.messages.back() == s.messages[599]);
    Bytes zeroTail = readAll(path + ".partial");  // a power loss can leave zero bytes at the end
    zeroTail.resize(zeroTail.size() + 5000, 0);
    CHECK(parseMcap(zeroTail, "z", McapReadMode::Tolerant).messages.size() == 600);
    // Random cuts of the big finished file agree with the record walk too.
    writeSession(path, s, kUnchunked);
    const Bytes full = readAll(path);
    const std::vector<std::size_t> ends = messageEnds(full);
    std::mt19937 rng(99);
    for (int i = 0; i < 150; ++i) {
        const std::size_t cut = rng() % full.size();
        const McapFile g =
            parseMcap(Bytes(full.begin(), full.begin() + std::ptrdiff_t(cut)), "c", McapReadMode::Tolerant);
        REQUIRE(g.messages.size() == std::size_t(std::upper_bound(ends.begin(), ends.end(), cut) - ends.begin()));
    }
}

TEST_CASE("mcap reader refuses malformed input and skips unknown records", "[mcap]") {
    // Hand-made file: Header, an application record (0x80), a Channel without schema, a Message.
    Bytes b = kMagic;
    b.push_back(0x01), le(b, 8, 8), str(b, ""), str(b, "");
    b.push_back(0x80), le(b, 3, 8), b.insert(b.end(), {9, 9, 9});
    b.push_back(0x04), le(b, 2 + 2 + 6 + 8 + 4, 8), le(b, 5, 2), le(b, 0, 2), str(b, "/x"), str(b, "json"), le(b, 0, 4);
    b.push_back(0x05), le(b, 23, 8), le(b, 5, 2), le(b, 0, 4), le(b, 1, 8), le(b, 1, 8), b.push_back('{');
    b.push_back(0x0F), le(b, 4, 8), le(b, 0, 4);  // CRC 0: not computed
    b.push_back(0x02), le(b, 20, 8), le(b, 0, 20);
    b.insert(b.end(), kMagic.begin(), kMagic.end());
    const McapFile f = parseMcap(b, "hand.mcap");
    REQUIRE(f.messages.size() == 1);
    CHECK(f.messages[0].data == Bytes{'{'});
    CHECK(f.channels.at(0).topic == "/x");

    Bytes huge = b;  // Channel record length 2^64 - 1
    std::fill(huge.begin() + 38, huge.begin() + 46, 0xFF);
    CHECK(strictFails(huge, "longer than the rest of the file"));
    CHECK(parseMcap(huge, "h", McapReadMode::Tolerant).channels.empty());
    Bytes longString = b;  // topic length 0xFFFFFFFF inside a complete record
    std::fill(longString.begin() + 50, longString.begin() + 54, 0xFF);
    CHECK(strictFails(longString, "claims 4294967295 bytes"));
    Bytes chunk = b;
    chunk[25] = 0x06;
    CHECK(strictFails(chunk, "Chunk record (opcode 6) at offset 25: message_start_time claims 8 bytes"));
    CHECK(strictFails(Bytes{'P', 'K', 3, 4, 0, 0, 0, 0, 0}, "not an MCAP file"));

    std::mt19937 rng(3);  // random damage: a bop::Error or a result, never a crash or another exception
    for (int i = 0; i < 3000; ++i) {
        Bytes d = b;
        for (int k = 0; k < 1 + i % 3; ++k) d[rng() % d.size()] = std::uint8_t(rng());
        for (auto mode : {McapReadMode::Strict, McapReadMode::Tolerant}) {
            try {
                parseMcap(d, "fuzz", mode);
            } catch (const bop::Error&) {
            }
        }
    }
}

TEST_CASE("mcap writer and reader errors name the file", "[mcap]") {
    const std::string path = tempPath("errors.mcap");
    McapWriter w(path);
    CHECK_THROWS_WITH(w.addChannel(4, "/a", "flatbuffer"),
                      Catch::Contains("errors.mcap.partial") && Catch::Contains("unknown schema id 4"));
    CHECK_THROWS_WITH(w.write(1, 0, 0, 0, Bytes{}), Catch::Contains("unknown channel id 1"));
    w.close();
    CHECK_THROWS_WITH(w.addSchema("s", "", Bytes{}), Catch::Contains("already closed"));
    CHECK_THROWS_WITH(McapWriter(tempPath("no/such/dir/x.mcap")), Catch::Contains("x.mcap.partial"));
    CHECK_THROWS_WITH(readMcap(tempPath("missing.mcap")), Catch::Contains("missing.mcap"));
    CHECK_THROWS_WITH(readMcap(path, McapReadMode::Strict, 100), Catch::Contains("more than the 100"));
    CHECK(readMcap(path).messages.empty());
}
