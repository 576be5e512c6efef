// Datagram mode over real sockets on 127.0.0.1 ephemeral ports: UdpSocket (bind, send,
// receive with a timeout, errors) and UdpSender / UdpReceiver end to end.
#include "bop/common/Error.hpp"
#include "transport/UdpSocket.hpp"
#include "transport/UdpStream.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

using namespace bop::protocol;
using Bytes = std::vector<std::uint8_t>;

namespace {

Bytes randomBytes(std::mt19937& rng, std::size_t n) {
    Bytes b(n);
    for (auto& x : b) x = static_cast<std::uint8_t>(rng());
    return b;
}

}  // namespace

TEST_CASE("UDP socket binds an ephemeral port, sends, receives and times out", "[protocol][udp]") {
    UdpSocket a, b;
    CHECK((a.boundPort() != 0 && a.boundPort() != b.boundPort()));
    CHECK(a.receive(0) == std::nullopt);
    const auto t0 = std::chrono::steady_clock::now();
    CHECK(a.receive(30) == std::nullopt);
    CHECK(std::chrono::steady_clock::now() - t0 >= std::chrono::milliseconds(29));
    const Bytes hello = {1, 2, 3};
    REQUIRE(b.sendTo({"127.0.0.1", a.boundPort()}, hello));
    const auto d = a.receive(1000);
    REQUIRE(d);
    CHECK((d->bytes == hello && d->sender == Endpoint{"127.0.0.1", b.boundPort()}));
    CHECK(b.sendTo(a.local(), Bytes{}));  // an empty datagram is a datagram
    REQUIRE(a.receive(1000));
    CHECK_THROWS_WITH(UdpSocket("localhost"), Catch::Contains("localhost"));
    CHECK_THROWS_WITH(UdpSocket("127.0.0.1", a.boundPort()), Catch::Contains(std::to_string(a.boundPort())));
    CHECK_THROWS_AS(b.sendTo({"127.0.0.1", a.boundPort()}, Bytes(70'000)), bop::Error);
    UdpSocket moved = std::move(a);
    CHECK_THROWS_AS(a.receive(0), bop::Error);  // NOLINT(bugprone-use-after-move): on purpose
}

TEST_CASE("loopback: a 3 MB message and 100 small messages arrive byte exact", "[protocol][udp]") {
    std::mt19937 rng(9);
    const Bytes big = randomBytes(rng, 3'000'000), medium = randomBytes(rng, 60'000);
    std::vector<Bytes> small;
    for (int i = 0; i < 100; ++i) small.push_back(randomBytes(rng, 1 + rng() % 3000));

    // One thread, sending in chunks and reading between them, so that no more than a chunk is
    // queued at a time: a 208 KiB receive buffer (Linux's usual net.core.rmem_max) holds it,
    // and a loaded machine that deschedules a reader thread cannot make the test drop datagrams.
    UdpReceiver receiver{UdpSocket{"127.0.0.1", 0, 208 * 1024}};
    INFO("receive buffer granted: " << receiver.socket().receiveBufferBytes() << " bytes");
    UdpSenderOptions pacing;  // exercised on the 50 datagrams of the medium message
    pacing.burstDatagrams = 16;
    pacing.burstPause = std::chrono::microseconds(100);
    UdpSender sender{UdpSocket{}, receiver.socket().local(), pacing};
    std::vector<Message> got;
    const auto collect = [&](int timeoutMs) {
        auto batch = receiver.receive(timeoutMs);
        for (Message& m : batch) got.push_back(std::move(m));
        return !batch.empty();
    };

    // The big message fragment by fragment, as UdpSender does, 32 datagrams (~40 KB) a chunk;
    // sent again under a new sequence if a datagram was lost all the same.
    std::uint32_t bigSent = 0;
    Bytes datagram;
    const auto bigArrived = [&] {
        return std::any_of(got.begin(), got.end(), [](const Message& m) { return m.stream == 0; });
    };
    for (; bigSent < 3 && !bigArrived(); ++bigSent) {
        const std::uint32_t count = fragmentCount(big.size(), kDefaultFragmentPayloadBytes);
        for (std::uint32_t i = 0; i < count; ++i) {
            writeFragment(datagram, 0, bigSent, big, kDefaultFragmentPayloadBytes, i);
            REQUIRE(sender.socket().sendTo(receiver.socket().local(), datagram));
            if (i % 32 == 31) collect(0);
        }
        collect(1000);
    }
    sender.send(2, medium);
    while (collect(1000) && !std::any_of(got.begin(), got.end(), [](auto& m) { return m.stream == 2; })) {
    }
    for (std::size_t i = 0; i < small.size(); ++i) {
        sender.send(1, small[i]);
        if (i % 10 == 9) collect(0);
    }
    while (collect(200)) {
    }

    REQUIRE(bigArrived());
    std::size_t smallGot = 0, mediumGot = 0;
    std::uint32_t lastSmall = 0;
    for (const Message& m : got) {
        if (m.stream == 0) {
            CHECK((m.bytes == big && m.sequence < bigSent));
        } else if (m.stream == 2) {
            CHECK((m.bytes == medium && m.sequence == 0));
            ++mediumGot;
        } else {
            REQUIRE(m.sequence < small.size());
            CHECK(m.bytes == small[m.sequence]);
            CHECK((smallGot == 0 || m.sequence > lastSmall));  // newest wins: increasing
            lastSmall = m.sequence;
            ++smallGot;
        }
    }
    CHECK(mediumGot == 1);
    CHECK(smallGot >= 10);  // the newest of each chunk of 10, unless one was lost
    const ReassemblyStats& s = receiver.stats();
    const std::uint64_t sent = bigSent + 1 + small.size();
    CHECK(s.delivered == got.size() + receiver.superseded());
    CHECK(s.delivered + s.lost + s.stale + receiver.partialMessages() <= sent);
    CHECK((s.malformed == 0 && s.oversized == 0 && s.duplicates == 0));
    CHECK(sender.stats().messages == 1 + small.size());
    CHECK(sender.stats().datagramsDropped == 0);
    if (receiver.datagrams() == sender.stats().datagrams + bigSent * 2500u)  // nothing lost
        CHECK((s.delivered == sent && s.lost == 0));
}
