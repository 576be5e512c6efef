// Untrusted bytes: truncated, flipped, oversized, misaligned or mislabelled buffers are refused
// with a reason (or, for a flip that leaves a valid message, decoded to a valid value); none
// crashes or reads outside the buffer (run under the sanitizer build to see the latter).
#include "ProtocolSamples.hpp"

#include <catch2/catch.hpp>

#include <cstring>
#include <random>

using namespace bop::protocol;
using namespace bop::protocol::samples;

TEST_CASE("every strict prefix of a valid buffer is refused", "[protocol]") {
    for (const Sample& s : allSamples()) {
        std::size_t accepted = 0;
        for (std::size_t len = 0; len < s.bytes.size(); ++len) {
            // An exact-size copy, so that a read past the prefix is a heap overflow under ASan.
            const Buffer prefix(s.bytes.begin(), s.bytes.begin() + std::ptrdiff_t(len));
            const DecodeCheck d = decodeAs(s.kind, prefix.data(), prefix.size());
            if (d.error == DecodeError::None) {
                // Only trailing alignment padding may be cut off without losing data (FlatBuffers
                // pads arrays and strings to 4 or 8 bytes); what decodes must be the original.
                ++accepted;
                INFO(toString(s.kind) << " prefix of " << len << " of " << s.bytes.size() << " bytes accepted");
                CHECK(len + 8 > s.bytes.size());
                CHECK(decodesToSameAs(s.kind, prefix.data(), prefix.size(), s.bytes));
            }
        }
        CHECK(accepted < 8);
        // Fewer than 8 bytes is always TooShort.
        CHECK(decodeAs(s.kind, s.bytes.data(), 7).error == DecodeError::TooShort);
        CHECK(decodeAs(s.kind, nullptr, 0).error == DecodeError::TooShort);
    }
}

TEST_CASE("random byte flips are refused or decode to valid values", "[protocol]") {
    std::mt19937 rng(2024);
    std::size_t refused = 0, decoded = 0;
    for (const Sample& s : allSamples()) {
        std::uniform_int_distribution<std::size_t> pos(0, s.bytes.size() - 1);
        std::uniform_int_distribution<int> byte(0, 255), flips(1, 4);
        for (int trial = 0; trial < 1500; ++trial) {
            Buffer b = s.bytes;
            for (int k = flips(rng); k > 0; --k) b[pos(rng)] ^= std::uint8_t(1 + byte(rng) % 255);
            // decodeAs re-encodes whatever is accepted, which throws on a value the decoder should
            // have refused, and reports whether the value survives a second round trip.
            const DecodeCheck d = decodeAs(s.kind, b.data(), b.size());
            if (d.error == DecodeError::None) {
                ++decoded;
                INFO(toString(s.kind) << " trial " << trial);
                CHECK(d.stable);
            } else {
                ++refused;
            }
        }
    }
    // Both outcomes occur: flips in offsets are caught, flips in plain values pass as values.
    CHECK(refused > 1000);
    CHECK(decoded > 1000);
}

TEST_CASE("oversized buffers are refused before verification", "[protocol]") {
    // A valid probe followed by zeros verifies (FlatBuffers ignores trailing bytes) but is over the cap.
    Buffer probe = encodeProbe(sampleProbe());
    const std::size_t valid = probe.size();
    probe.resize(kMaxProbeBytes, 0);
    CHECK(decodeProbe(probe.data(), probe.size()).ok());
    probe.push_back(0);
    const Decoded<Probe> p = decodeProbe(probe.data(), probe.size());
    CHECK(p.error == DecodeError::TooLarge);
    CHECK(p.message.find("257 bytes") != std::string::npos);
    CHECK(valid < kMaxProbeBytes);

    // Garbage over a cap reports the size, not the garbage.
    const Buffer garbage(kMaxCommandBytes + 1, 0xAB);
    CHECK(decodeCommand(garbage.data(), garbage.size()).error == DecodeError::TooLarge);
    CHECK(decodeHello(garbage.data(), kMaxHelloBytes + 1).error == DecodeError::TooLarge);
    CHECK(decodeHello(garbage.data(), kMaxHelloBytes).error == DecodeError::WrongIdentifier);

    // The frame cap is the receiver's choice.
    const Buffer frame = encodeStateFrame(sampleFrame(400, FrameEncoding::Float32, true, false));
    FrameLimits small;
    small.maxChunkBytes = frame.size() - 1;
    CHECK(decodeStateFrame(frame.data(), frame.size(), small).error == DecodeError::TooLarge);
    small.maxChunkBytes = frame.size();
    CHECK(decodeStateFrame(frame.data(), frame.size(), small).ok());
}

TEST_CASE("a buffer of another message or with a bad identifier is refused", "[protocol]") {
    const Buffer probe = encodeProbe(sampleProbe());
    const Decoded<Feedback> f = decodeFeedback(probe.data(), probe.size());
    CHECK(f.error == DecodeError::WrongIdentifier);
    CHECK(f.message.find("Probe") != std::string::npos);  // says what the buffer holds
    for (const Sample& s : allSamples()) {
        Buffer b = s.bytes;
        b[5] ^= 0x20;  // "BPRB" -> "BpRB"
        CHECK(decodeAs(s.kind, b.data(), b.size()).error == DecodeError::WrongIdentifier);
        CHECK(messageKind(b.data(), b.size()) == MessageKind::Unknown);
    }
}

TEST_CASE("misaligned buffers decode like aligned ones", "[protocol]") {
    for (const Sample& s : allSamples()) {
        std::vector<std::uint8_t> storage(s.bytes.size() + 3);
        std::memcpy(storage.data() + 3, s.bytes.data(), s.bytes.size());
        const std::uint8_t* odd = storage.data() + 3;
        INFO(toString(s.kind));
        CHECK(decodesToSameAs(s.kind, odd, s.bytes.size(), s.bytes));
    }
}
