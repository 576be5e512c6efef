// Datagram mode without sockets: fragment layout, reassembly under loss, reordering,
// duplicates and hostile input (UdpFragments.hpp). Real sockets: TestUdpSocket.cpp.
#include "bop/common/Error.hpp"
#include "transport/UdpFragments.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

using namespace bop::protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

Bytes randomBytes(std::mt19937& rng, std::size_t n) {
    Bytes b(n);
    for (auto& x : b) x = static_cast<std::uint8_t>(rng());
    return b;
}

// A datagram packed here by hand, independently of writeFragment, with every field chosen.
Bytes handDatagram(std::uint8_t stream, std::uint32_t seq, std::uint32_t index, std::uint32_t count,
                   std::uint32_t total, std::uint16_t stride, const Bytes& payload, std::uint8_t version = 1) {
    Bytes d = {'B', 'F', version, stream};
    for (std::uint32_t v : {seq, index, count, total})
        for (int i = 0; i < 4; ++i) d.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    d.push_back(static_cast<std::uint8_t>(stride));
    d.push_back(static_cast<std::uint8_t>(stride >> 8));
    d.insert(d.end(), payload.begin(), payload.end());
    return d;
}

// Feeds datagrams; returns the messages delivered, in order.
std::vector<Message> feed(Reassembler& r, const std::vector<Bytes>& datagrams) {
    std::vector<Message> out;
    for (const Bytes& d : datagrams)
        if (auto m = r.accept(d)) out.push_back(std::move(*m));
    return out;
}

}  // namespace

TEST_CASE("UDP fragments carry the documented header and split the message exactly", "[protocol][udp]") {
    std::mt19937 rng(1);
    const Bytes msg = randomBytes(rng, 2500);
    const auto d = splitMessage(7, 0x01020304u, msg, 1000);
    REQUIRE(d.size() == 3);
    CHECK(d[0] == handDatagram(7, 0x01020304u, 0, 3, 2500, 1000, Bytes(msg.begin(), msg.begin() + 1000)));
    CHECK(d[2] == handDatagram(7, 0x01020304u, 2, 3, 2500, 1000, Bytes(msg.begin() + 2000, msg.end())));
    CHECK(d[1].size() == kFragmentHeaderBytes + 1000);
    CHECK(splitMessage(0, 0, msg, 1250).size() == 2);  // exact multiple: no empty last fragment
    const auto empty = splitMessage(0, 9, Bytes{});
    REQUIRE(empty.size() == 1);
    CHECK(empty[0].size() == kFragmentHeaderBytes);
    Reassembler r;
    auto m = r.accept(empty[0]);
    REQUIRE(m);
    CHECK((m->sequence == 9 && m->bytes.empty()));
    CHECK(fragmentCount(1'000'000 * 16, 1200) == 13334);  // > 65536 for larger frames: u32 index
    CHECK_THROWS_AS(fragmentCount(10, 0), bop::Error);
    CHECK_THROWS_AS(fragmentCount(10, kMaxFragmentPayloadBytes + 1), bop::Error);
}

TEST_CASE("reassembly in random order with duplicates delivers the exact bytes once", "[protocol][udp]") {
    std::mt19937 rng(2);
    const Bytes a = randomBytes(rng, 100'000), b = randomBytes(rng, 33'333);
    std::vector<Bytes> d = splitMessage(0, 41, a), db = splitMessage(1, 41, b, 500);
    d.insert(d.end(), db.begin(), db.end());  // two streams, same sequence: independent
    const std::size_t unique = d.size();
    for (std::size_t i = 0; i < unique; i += 3) d.push_back(d[i]);  // every third one twice
    std::shuffle(d.begin(), d.end(), rng);
    Reassembler r;
    const auto got = feed(r, d);
    REQUIRE(got.size() == 2);
    const Message& ma = got[0].stream == 0 ? got[0] : got[1];
    const Message& mb = got[0].stream == 0 ? got[1] : got[0];
    CHECK((ma.bytes == a && mb.bytes == b && ma.sequence == 41 && mb.sequence == 41));
    CHECK(r.stats().delivered == 2);
    CHECK(r.stats().duplicates == d.size() - unique);
    CHECK((r.stats().lost == 0 && r.stats().malformed == 0 && r.partialMessages() == 0));
    CHECK(r.bufferedBytes() == 0);
}

TEST_CASE("under 10 and 30 percent datagram loss only complete messages are delivered", "[protocol][udp]") {
    for (const double dropRate : {0.1, 0.3}) {
        std::mt19937 rng(dropRate < 0.2 ? 3 : 4);
        std::bernoulli_distribution drop(dropRate);
        std::map<std::uint32_t, Bytes> sent;
        std::uint64_t complete = 0, incomplete = 0;  // messages with all / some datagrams kept
        std::vector<Bytes> stream;
        const std::uint32_t messages = 300;
        for (std::uint32_t seq = 0; seq <= messages; ++seq) {
            // The last message is sent without loss, so every incomplete one is superseded.
            const Bytes msg = randomBytes(rng, 1 + rng() % 20'000);  // 1 to 17 fragments
            sent[seq] = msg;
            auto d = splitMessage(0, seq, msg);
            std::shuffle(d.begin(), d.end(), rng);
            std::size_t kept = 0;
            for (auto& x : d)
                if (seq == messages || !drop(rng)) stream.push_back(std::move(x)), ++kept;
            if (kept == d.size())
                ++complete;
            else if (kept > 0)
                ++incomplete;
        }
        Reassembler r;
        const auto got = feed(r, stream);
        CAPTURE(dropRate, complete, incomplete);
        REQUIRE(got.size() == complete);
        for (const Message& m : got) CHECK(m.bytes == sent.at(m.sequence));
        CHECK(r.stats().delivered == complete);
        CHECK(r.stats().lost == incomplete);
        CHECK((r.stats().stale == 0 && r.stats().malformed == 0 && r.stats().duplicates == 0));
        CHECK((r.partialMessages() == 0 && r.bufferedBytes() == 0));
        CHECK((incomplete > 10 && complete > 10));  // the case exercises both outcomes
    }
}

TEST_CASE("newest wins: older messages are stale or lost once a newer one is delivered", "[protocol][udp]") {
    std::mt19937 rng(5);
    const Bytes m5 = randomBytes(rng, 3000), m6 = randomBytes(rng, 3000);
    const Bytes m7 = randomBytes(rng, 3000), m8 = randomBytes(rng, 3000);
    const auto d5 = splitMessage(0, 5, m5), d6 = splitMessage(0, 6, m6);
    const auto d7 = splitMessage(0, 7, m7), d8 = splitMessage(0, 8, m8);
    Reassembler r;
    REQUIRE(feed(r, d6).size() == 1);
    CHECK(feed(r, d5).empty());  // complete, but older than 6
    CHECK((r.stats().stale == 1 && r.stats().late == d5.size() - 1));
    CHECK(r.accept(d7[0]) == std::nullopt);  // 7 partial ...
    const auto got = feed(r, d8);            // ... superseded by 8
    REQUIRE(got.size() == 1);
    CHECK((got[0].sequence == 8 && got[0].bytes == m8));
    CHECK((r.stats().lost == 1 && r.partialMessages() == 0));
    CHECK(feed(r, d7).empty());  // the rest of 7 comes too late
    CHECK(r.stats().late == d5.size() - 1 + d7.size());
    CHECK(r.accept(d8[1]) == std::nullopt);
    CHECK(r.accept(d6[0]) == std::nullopt);
    CHECK(r.stats().duplicates == 2);
    CHECK(r.stats().delivered == 2);
}

TEST_CASE("reassembly limits: oversized messages, partial slots and total bytes", "[protocol][udp]") {
    CHECK_THROWS_AS(Reassembler(ReassemblyLimits{0, 1000, 1000}), bop::Error);
    CHECK_THROWS_AS(Reassembler(ReassemblyLimits{4, 2000, 1000}), bop::Error);
    std::mt19937 rng(6);
    Reassembler r(ReassemblyLimits{2, 10'000, 15'000});
    CHECK(feed(r, splitMessage(0, 1, randomBytes(rng, 10'001))).empty());
    CHECK(r.stats().oversized == 9);  // every datagram of it, nothing buffered
    CHECK(r.bufferedBytes() == 0);

    const Bytes a = randomBytes(rng, 8000), b = randomBytes(rng, 6000), c = randomBytes(rng, 5000);
    const auto da = splitMessage(0, 10, a), db = splitMessage(1, 20, b), dc = splitMessage(2, 30, c);
    r.accept(da[0]);
    r.accept(db[0]);
    CHECK((r.partialMessages() == 2 && r.bufferedBytes() == 14'000));
    r.accept(dc[0]);  // 19000 bytes would exceed the cap: a, touched least recently, goes
    CHECK((r.stats().lost == 1 && r.partialMessages() == 2 && r.bufferedBytes() == 11'000));
    CHECK(feed(r, da).empty());
    CHECK(r.stats().late == da.size());
    const auto got = feed(r, {db.begin() + 1, db.end()});
    REQUIRE(got.size() == 1);
    CHECK(got[0].bytes == b);
    REQUIRE(feed(r, {dc.begin() + 1, dc.end()}).size() == 1);

    // A third partial with room in bytes evicts by count.
    r.accept(splitMessage(3, 1, randomBytes(rng, 2000))[0]);
    r.accept(splitMessage(4, 1, randomBytes(rng, 2000))[0]);
    r.accept(splitMessage(5, 1, randomBytes(rng, 2000))[0]);
    CHECK((r.stats().lost == 2 && r.partialMessages() == 2 && r.bufferedBytes() == 4000));
}

TEST_CASE("malformed datagrams are counted and never crash the reassembler", "[protocol][udp]") {
    std::mt19937 rng(7);
    const Bytes msg = randomBytes(rng, 2500);
    const auto d = splitMessage(3, 77, msg, 1000);
    Reassembler r;
    std::uint64_t bad = 0;
    for (const Bytes& x : d)  // every truncation of first, middle and last datagram
        for (std::size_t n = 0; n < x.size(); ++n, ++bad) CHECK(r.accept(std::span(x.data(), n)) == std::nullopt);
    CHECK(r.stats().malformed == bad);
    CHECK(r.partialMessages() == 0);

    const Bytes p1000(1000, 1), p500(500, 2);
    const std::vector<Bytes> hostile = {
        handDatagram(3, 77, 0, 3, 2500, 1000, p1000, 2),  // unknown header version
        handDatagram(3, 77, 3, 3, 2500, 1000, p1000),     // index >= count
        handDatagram(3, 77, 0, 4, 2500, 1000, p1000),     // count disagrees with total/stride
        handDatagram(3, 77, 0, 2, 2500, 1000, p1000),    handDatagram(3, 77, 0, 3, 2500, 0, p1000),  // stride 0
        handDatagram(3, 77, 2, 3, 2500, 1000, p1000),  // last carries 500, not 1000
        handDatagram(3, 77, 0, 0, 0, 1000, {}),        // no fragments
        handDatagram(3, 77, 0, 1, 0, 1000, p500),      // empty message with a payload
    };
    Bytes badMagic = d[0];
    badMagic[1] = 'X';
    CHECK(feed(r, hostile).empty());
    CHECK(r.accept(badMagic) == std::nullopt);
    CHECK(r.stats().malformed == bad + hostile.size() + 1);

    // Well formed on its own, but not with the fragment of message 77 already held.
    REQUIRE(r.accept(d[0]) == std::nullopt);
    CHECK(r.accept(handDatagram(3, 77, 1, 4, 3500, 1000, p1000)) == std::nullopt);
    CHECK(r.accept(handDatagram(3, 77, 1, 5, 2500, 500, p500)) == std::nullopt);
    CHECK(r.stats().malformed == bad + hostile.size() + 3);
    const auto got = feed(r, {d[1], d[2]});
    REQUIRE(got.size() == 1);
    CHECK(got[0].bytes == msg);

    // Random bytes, half of them behind a valid magic and version.
    const ReassemblyStats before = r.stats();
    for (int i = 0; i < 20'000; ++i) {
        Bytes x = randomBytes(rng, rng() % 64);
        if (i % 2 == 0 && x.size() >= 3) x[0] = 'B', x[1] = 'F', x[2] = 1;
        r.accept(x);
        REQUIRE(r.partialMessages() <= 4);
        REQUIRE(r.bufferedBytes() <= ReassemblyLimits{}.maxTotalBytes);
    }
    CHECK(r.stats().malformed - before.malformed >= 19'900);
}

TEST_CASE("sequence numbers compare across the 2^32 wrap", "[protocol][udp]") {
    CHECK(sequenceNewer(0, 0xFFFFFFFFu));
    CHECK(sequenceNewer(5, 0xFFFFFFF0u));
    CHECK_FALSE(sequenceNewer(0xFFFFFFFFu, 0));
    CHECK_FALSE(sequenceNewer(7, 7));
    CHECK_FALSE(sequenceNewer(0x80000000u, 0));  // half the circle away: neither
    CHECK_FALSE(sequenceNewer(0, 0x80000000u));
    std::mt19937 rng(8);
    Reassembler r;
    for (std::uint32_t seq : {0xFFFFFFFEu, 0xFFFFFFFFu, 0u, 1u}) {
        const Bytes msg = randomBytes(rng, 4000);
        const auto got = feed(r, splitMessage(0, seq, msg));
        REQUIRE(got.size() == 1);
        CHECK((got[0].sequence == seq && got[0].bytes == msg));
    }
    CHECK(feed(r, splitMessage(0, 0xFFFFFFF0u, randomBytes(rng, 4000))).empty());
    CHECK(r.stats().stale == 1);
    r.accept(splitMessage(0, 2, randomBytes(rng, 4000))[0]);  // partial 2, superseded by 3
    REQUIRE(feed(r, splitMessage(0, 3, randomBytes(rng, 10))).size() == 1);
    CHECK((r.stats().lost == 1 && r.stats().delivered == 5));
}
