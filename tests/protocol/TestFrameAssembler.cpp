// Frame reassembly without sockets (client/FrameAssembler.hpp): real chunks from the encoder,
// decoded as a receiver decodes them, fed in every order, with losses, stale frames, chunks that
// disagree and hostile sizes.
#include "ProtocolSamples.hpp"
#include "client/FrameAssembler.hpp"
#include "codec/Codec.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <vector>

using namespace bop::protocol;

namespace {

// Particles with normals and ids on the wire, bytes: positions, normals, species, ids.
constexpr std::size_t kBytesPerParticle = 12 + 12 + 1 + 8;  // Float32
constexpr std::size_t kQuantisedBytesPerParticle = 6 + 4 + 1 + 8;
// What encodeStateFrameChunks keeps free for the header of each chunk (FrameCodec.cpp), bytes.
constexpr std::size_t kChunkOverhead = 1024;

StateFrame frameWith(std::uint64_t seq, std::size_t n, FrameEncoding encoding = FrameEncoding::Float32) {
    StateFrame f = samples::sampleFrame(n, encoding, true, true, std::uint32_t(seq));
    f.frameSeq = seq;
    f.step = 100 * seq;
    return f;
}

StateFrame decoded(const Buffer& b) {
    auto d = decodeStateFrame(b.data(), b.size());
    REQUIRE(d.ok());
    return d.value;
}

// The frame as the encoder splits it into chunks of at most `perChunk` particles, each decoded.
std::vector<StateFrame> chunksOf(const StateFrame& whole, std::size_t perChunk) {
    const std::size_t bpp = whole.encoding == FrameEncoding::Float32 ? kBytesPerParticle : kQuantisedBytesPerParticle;
    std::vector<StateFrame> out;
    for (const Buffer& b : encodeStateFrameChunks(whole, kChunkOverhead + perChunk * bpp)) out.push_back(decoded(b));
    return out;
}

// Particles [begin, end) of `whole` as chunk `index` of `count` starting at frame index `first`,
// built by hand (for chunk sets no encoder makes), encoded and decoded.
StateFrame handChunk(const StateFrame& whole, std::size_t begin, std::size_t end, std::uint32_t index,
                     std::uint32_t count, std::uint32_t first) {
    StateFrame c = whole;
    c.chunkIndex = index;
    c.chunkCount = count;
    c.firstIndex = first;
    c.positions.assign(whole.positions.begin() + 3 * begin, whole.positions.begin() + 3 * end);
    c.normals.assign(whole.normals.begin() + 3 * begin, whole.normals.begin() + 3 * end);
    c.species.assign(whole.species.begin() + begin, whole.species.begin() + end);
    c.ids.assign(whole.ids.begin() + begin, whole.ids.begin() + end);
    return decoded(encodeStateFrame(c));
}

// Feeds all chunks; returns what the last one delivered (the earlier ones must deliver nothing).
std::optional<StateFrame> feedAll(FrameAssembler& a, const std::vector<StateFrame>& chunks) {
    for (std::size_t k = 0; k + 1 < chunks.size(); ++k) REQUIRE_FALSE(a.add(chunks[k]).has_value());
    return a.add(chunks.back());
}

}  // namespace

TEST_CASE("FrameAssembler: chunks in any order give the exact frame", "[protocol][client]") {
    for (const FrameEncoding encoding : {FrameEncoding::Float32, FrameEncoding::Quantised16}) {
        const StateFrame whole = frameWith(5, 37, encoding);
        const StateFrame expected = decoded(encodeStateFrame(whole));  // quantised values as a receiver sees them
        const std::vector<StateFrame> chunks = chunksOf(whole, 10);
        REQUIRE(chunks.size() == 4);
        std::vector<std::size_t> order(chunks.size());
        std::iota(order.begin(), order.end(), 0);
        int permutations = 0;
        do {
            FrameAssembler a;
            std::vector<StateFrame> shuffled;
            for (std::size_t k : order) shuffled.push_back(chunks[k]);
            const auto frame = feedAll(a, shuffled);
            REQUIRE(frame.has_value());
            CHECK(samples::same(*frame, expected));
            CHECK(a.stats().delivered == 1);
            CHECK(a.partialFrames() == 0);
            CHECK(a.partialBytes() == 0);
            ++permutations;
        } while (std::next_permutation(order.begin(), order.end()));
        CHECK(permutations == 24);
    }
}

TEST_CASE("FrameAssembler: whole frames pass straight through, newest wins", "[protocol][client]") {
    FrameAssembler a;
    const auto one = a.add(decoded(encodeStateFrame(frameWith(1, 5))));
    REQUIRE(one.has_value());
    CHECK(samples::same(*one, decoded(encodeStateFrame(frameWith(1, 5)))));
    CHECK(a.add(decoded(encodeStateFrame(frameWith(3, 5)))).has_value());
    CHECK_FALSE(a.add(decoded(encodeStateFrame(frameWith(2, 5)))).has_value());  // older than 3
    CHECK_FALSE(a.add(decoded(encodeStateFrame(frameWith(3, 5)))).has_value());  // 3 again
    CHECK(a.stats().delivered == 2);
    CHECK(a.stats().stale == 2);
    CHECK(a.lastDelivered() == 3u);
    // An empty frame is a whole frame too.
    CHECK(a.add(decoded(encodeStateFrame(frameWith(4, 0)))).has_value());
}

TEST_CASE("FrameAssembler: a missing chunk holds its frame back; a newer whole frame makes it lost",
          "[protocol][client]") {
    FrameAssembler a;
    const std::vector<StateFrame> five = chunksOf(frameWith(5, 40), 10), six = chunksOf(frameWith(6, 40), 10);
    for (int k : {0, 1, 3}) CHECK_FALSE(a.add(five[k]).has_value());
    CHECK(a.partialFrames() == 1);
    CHECK(a.partialBytes() == 40 * (12 + 12 + 1 + 8));  // the whole frame's room, taken at its first chunk
    CHECK(a.stats().lost == 0);
    const auto frame = feedAll(a, six);
    REQUIRE(frame.has_value());
    CHECK(frame->frameSeq == 6);
    CHECK(a.stats().lost == 1);
    CHECK(a.partialFrames() == 0);
    CHECK_FALSE(a.add(five[2]).has_value());  // too late: stale
    CHECK(a.stats().stale == 1);
    CHECK(a.stats().delivered == 1);
}

TEST_CASE("FrameAssembler: interleaved frames, the newer completing first", "[protocol][client]") {
    FrameAssembler a;
    const std::vector<StateFrame> seven = chunksOf(frameWith(7, 30), 10), eight = chunksOf(frameWith(8, 30), 10);
    CHECK_FALSE(a.add(seven[0]).has_value());
    CHECK_FALSE(a.add(eight[0]).has_value());
    CHECK_FALSE(a.add(seven[1]).has_value());
    CHECK_FALSE(a.add(eight[2]).has_value());
    const auto frame = a.add(eight[1]);
    REQUIRE(frame.has_value());
    CHECK(samples::same(*frame, decoded(encodeStateFrame(frameWith(8, 30)))));
    CHECK_FALSE(a.add(seven[2]).has_value());
    CHECK(a.stats().lost == 1);
    CHECK(a.stats().stale == 1);
    // And the older completing first is delivered, the newer still to come.
    CHECK(feedAll(a, chunksOf(frameWith(9, 30), 10)).has_value());
    CHECK(a.stats().delivered == 2);
}

TEST_CASE("FrameAssembler: chunks that disagree are refused and counted", "[protocol][client]") {
    const StateFrame whole = frameWith(11, 20);
    FrameAssembler a;
    bool multiChunk = true;
    SECTION("overlap") {
        CHECK_FALSE(a.add(handChunk(whole, 0, 12, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(whole, 10, 20, 1, 2, 10)).has_value());
    }
    SECTION("gap") {
        CHECK_FALSE(a.add(handChunk(whole, 0, 8, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(whole, 10, 20, 1, 2, 10)).has_value());
    }
    SECTION("two chunks at one first index") {
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(whole, 10, 20, 1, 2, 0)).has_value());
    }
    SECTION("a chunk index twice") {
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 3, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(whole, 10, 15, 0, 3, 10)).has_value());
    }
    SECTION("different chunk counts") {
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(whole, 10, 20, 1, 3, 10)).has_value());
    }
    SECTION("different particle counts") {
        StateFrame longer = whole;
        longer.frameParticleCount = 25;
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(longer, 10, 20, 1, 2, 10)).has_value());
    }
    SECTION("different steps") {
        StateFrame later = whole;
        later.step += 1;
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 2, 0)).has_value());
        CHECK_FALSE(a.add(handChunk(later, 10, 20, 1, 2, 10)).has_value());
    }
    SECTION("a whole frame that does not fill itself") {
        multiChunk = false;
        CHECK_FALSE(a.add(handChunk(whole, 0, 10, 0, 1, 5)).has_value());
    }
    CHECK(a.stats().inconsistent == 1);
    CHECK(a.stats().delivered == 0);
    CHECK(a.partialBytes() == 0);
    // Further chunks of a refused frame are ignored, not counted again; later frames still come.
    if (multiChunk) {
        CHECK_FALSE(a.add(handChunk(whole, 10, 20, 1, 2, 10)).has_value());
        CHECK(a.stats().inconsistent == 1);
    }
    CHECK(feedAll(a, chunksOf(frameWith(12, 20), 10)).has_value());
    CHECK(a.stats().lost == 0);  // a refused frame is not also lost
}

TEST_CASE("FrameAssembler: bounded in partial frames and bytes", "[protocol][client]") {
    SECTION("the oldest partial frame goes first") {
        FrameAssembler a(AssemblerLimits{2, std::size_t(1) << 20});
        for (std::uint64_t seq : {1, 2, 3}) a.add(chunksOf(frameWith(seq, 20), 10)[0]);
        CHECK(a.partialFrames() == 2);
        CHECK(a.stats().lost == 1);
        // Frame 2 completes; frame 3 is newer and stays.
        CHECK(a.add(chunksOf(frameWith(2, 20), 10)[1]).has_value());
        CHECK(a.partialFrames() == 1);
        CHECK(a.stats().lost == 1);
    }
    SECTION("a frame larger than the byte cap is given up once") {
        FrameAssembler a(AssemblerLimits{3, 15 * kBytesPerParticle});
        const std::vector<StateFrame> big = chunksOf(frameWith(4, 30), 10);
        CHECK_FALSE(a.add(big[0]).has_value());  // room for 30 particles: over the cap
        CHECK_FALSE(a.add(big[1]).has_value());
        CHECK_FALSE(a.add(big[2]).has_value());
        CHECK(a.stats().lost == 1);
        CHECK(a.partialBytes() == 0);
        CHECK(a.add(decoded(encodeStateFrame(frameWith(5, 30)))).has_value());  // whole frames need no room
    }
}

TEST_CASE("FrameAssembler: a run of stale chunks means the sender restarted its numbering", "[protocol][client]") {
    FrameAssembler a;
    REQUIRE(a.add(decoded(encodeStateFrame(frameWith(100, 5)))).has_value());
    // A restarted server numbers from 1 again: 15 chunks are taken as stale, the 16th starts over.
    for (std::uint64_t seq = 1; seq < 16; ++seq)
        CHECK_FALSE(a.add(decoded(encodeStateFrame(frameWith(seq, 5)))).has_value());
    const auto frame = a.add(decoded(encodeStateFrame(frameWith(16, 5))));
    REQUIRE(frame.has_value());
    CHECK(frame->frameSeq == 16);
    CHECK(a.stats().stale == 15);
    CHECK(a.stats().restarts == 1);
    CHECK(a.add(decoded(encodeStateFrame(frameWith(17, 5)))).has_value());
    // A shorter run does not: the count starts again at every chunk that is not stale.
    for (std::uint64_t seq = 1; seq < 16; ++seq) a.add(decoded(encodeStateFrame(frameWith(seq, 5))));
    CHECK(a.add(decoded(encodeStateFrame(frameWith(18, 5)))).has_value());
    for (std::uint64_t seq = 1; seq < 16; ++seq) a.add(decoded(encodeStateFrame(frameWith(seq, 5))));
    CHECK(a.stats().restarts == 1);
    // And never, when asked.
    FrameAssembler strict(AssemblerLimits{3, std::size_t(1) << 20, 0});
    REQUIRE(strict.add(decoded(encodeStateFrame(frameWith(100, 5)))).has_value());
    for (std::uint64_t seq = 1; seq < 50; ++seq)
        CHECK_FALSE(strict.add(decoded(encodeStateFrame(frameWith(seq, 5)))).has_value());
    CHECK(strict.stats().restarts == 0);
}

TEST_CASE("FrameAssembler: frames given back lend their memory to later frames", "[protocol][client]") {
    FrameAssembler a;
    auto first = feedAll(a, chunksOf(frameWith(1, 40), 10));
    REQUIRE(first.has_value());
    const float* memory = first->positions.data();
    a.recycle(std::move(*first));
    const StateFrame second = frameWith(2, 40);
    const auto frame = feedAll(a, chunksOf(second, 10));
    REQUIRE(frame.has_value());
    CHECK(frame->positions.data() == memory);
    CHECK(samples::same(*frame, decoded(encodeStateFrame(second))));
    // A decoder fills a spare in place; what it held before does not show through.
    StateFrame spare = a.spare();
    CHECK(spare.positions.capacity() >= 3 * 10);
    const StateFrame small = frameWith(3, 4, FrameEncoding::Quantised16);
    const Buffer b = encodeStateFrame(small);
    REQUIRE(decodeStateFrameInto(b.data(), b.size(), spare).ok());
    CHECK(samples::same(spare, decoded(b)));
}
