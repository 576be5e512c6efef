// libFuzzer targets for the decoders of untrusted input: one source, one executable per target,
// chosen at compile time with -DBOP_FUZZ_TARGET=<name> (tests/fuzz/CMakeLists.txt):
//   hello scene frame probe feedback command reply   codec/Codec.hpp decoders
//   maprequest mapchunk mapedits refusal
//   mcap                                             recording/McapReader.hpp parseMcap
// Besides the sanitizers' findings, a target aborts when a decoder breaks its contract:
//   - a value it accepts must pass validate() and be accepted by the encoder (no EncodeError),
//   - encoded again and decoded again it must come back equal (frames: header, counts, arrays),
//     and encoding that second value must give the same bytes,
//   - the answer must not depend on the buffer's alignment (the input is decoded a second time
//     from an odd address, which takes the decoder's copy-to-aligned path).
// parseMcap runs in Strict and Tolerant mode; bop::Error is the expected refusal. A file that
// Strict accepts must read the same in Tolerant mode, and Tolerant mode must read the same records
// again from the first validBytes bytes of what it was given.
#include "ProtocolSamples.hpp"  // samples::same(): field-by-field comparisons of every message
#include "bop/common/Error.hpp"
#include "codec/Codec.hpp"
#include "codec/Validate.hpp"
#include "igtl/IgtlWire.hpp"
#include "recording/McapReader.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#ifndef BOP_FUZZ_TARGET
#error \
    "define BOP_FUZZ_TARGET: hello, scene, frame, probe, feedback, command, reply, maprequest, mapchunk, refusal, mcap or igtl"
#endif
#define BOP_FUZZ_STR2(x) #x
#define BOP_FUZZ_STR(x) BOP_FUZZ_STR2(x)

namespace {

using namespace bop::protocol;

constexpr std::string_view kTarget = BOP_FUZZ_STR(BOP_FUZZ_TARGET);
constexpr std::string_view kTargets[] = {"hello",   "scene", "frame",      "probe",    "feedback",
                                         "command", "reply", "maprequest", "mapchunk", "mapedits",
                                         "refusal", "mcap",  "igtl"};
constexpr bool knownTarget() {
    for (std::string_view t : kTargets)
        if (t == kTarget) return true;
    return false;
}
static_assert(knownTarget(),
              "BOP_FUZZ_TARGET must be hello, scene, frame, probe, feedback, command, reply, maprequest, mapchunk, "
              "mapedits, refusal, mcap or igtl");

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "\nFUZZ CONTRACT BROKEN (%.*s): %s\n", int(kTarget.size()), kTarget.data(), what.c_str());
    std::fflush(stderr);
    std::abort();
}

// The input again at an odd address, in an allocation of exactly len bytes after that address so
// that AddressSanitizer still sees a read past the end.
struct Misaligned {
    std::unique_ptr<std::uint8_t[]> storage;
    const std::uint8_t* data;
    Misaligned(const std::uint8_t* p, std::size_t len) : storage(new std::uint8_t[len + 1]), data(storage.get() + 1) {
        if (len) std::memcpy(storage.get() + 1, p, len);
    }
};

// decode: (const uint8_t*, size_t) -> Decoded<T>; encode: const T& -> Buffer.
template <class T, class Decode, class Encode, class Check>
void checkDecoder(const std::uint8_t* data, std::size_t size, Decode decode, Encode encode, Check validateValue) {
    const Decoded<T> d = decode(data, size);
    if (d.ok() != d.message.empty()) fail("ok() is " + std::to_string(d.ok()) + " but message is '" + d.message + "'");

    const Misaligned odd(data, size);
    const Decoded<T> dOdd = decode(odd.data, size);
    if (dOdd.error != d.error)
        fail(std::string("aligned input: ") + toString(d.error) + " (" + d.message +
             "), misaligned input: " + toString(dOdd.error) + " (" + dOdd.message + ")");
    if (!d.ok()) return;
    if (!bop::protocol::samples::same(d.value, dOdd.value))
        fail("aligned and misaligned input decode to different values");

    const Validation v = validateValue(d.value);
    if (!v.ok()) fail("the decoder accepted a value validate() refuses: " + v.message);

    Buffer again;
    try {
        again = encode(d.value);
    } catch (const EncodeError& e) {
        fail(std::string("the decoder accepted a value the encoder refuses: ") + e.what());
    }
    const Decoded<T> d2 = decode(again.data(), again.size());
    if (!d2.ok()) fail(std::string("the re-encoded value is refused: ") + toString(d2.error) + " (" + d2.message + ")");
    if (!bop::protocol::samples::same(d.value, d2.value)) fail("the value changed in the round trip");
    Buffer third;
    try {
        third = encode(d2.value);
    } catch (const EncodeError& e) {
        fail(std::string("the round-tripped value is refused by the encoder: ") + e.what());
    }
    if (third != again) fail("encode(decode(encode(v))) differs from encode(v) byte-wise");
}

template <class T>
auto validator() {
    return [](const T& m) { return validate(m); };
}

[[maybe_unused]] void checkFrame(const std::uint8_t* data, std::size_t size) {
    const FrameLimits limits;  // what a receiver uses by default (species 1..255)
    const auto decode = [&limits](const std::uint8_t* p, std::size_t n) { return decodeStateFrame(p, n, limits); };
    checkDecoder<StateFrame>(data, size, decode, &encodeStateFrame, [&limits](const StateFrame& m) {
        // Consumers index the arrays by count(); say precisely which invariant broke.
        const std::size_t n = m.count();
        if (m.positions.size() != 3 * n) fail("positions.size() != 3 * count()");
        if (!m.normals.empty() && m.normals.size() != 3 * n) fail("normals.size() is neither 0 nor 3 * count()");
        if (!m.ids.empty() && m.ids.size() != n) fail("ids.size() is neither 0 nor count()");
        if (m.chunkIndex >= m.chunkCount) fail("chunkIndex >= chunkCount");
        if (std::uint64_t(m.firstIndex) + n > m.frameParticleCount) fail("firstIndex + count() > frameParticleCount");
        return validate(m, limits);
    });
}

[[maybe_unused]] void checkMcap(const std::uint8_t* data, std::size_t size) {
    using namespace bop::recording;
    const std::span<const std::uint8_t> bytes(data, size);
    const auto sameFile = [](const McapFile& a, const McapFile& b) {
        return a.profile == b.profile && a.library == b.library && a.schemas == b.schemas && a.channels == b.channels &&
               a.messages == b.messages && a.statistics == b.statistics && a.hasDataEnd == b.hasDataEnd &&
               a.dataSectionCrc == b.dataSectionCrc && a.complete == b.complete && a.validBytes == b.validBytes;
    };

    std::optional<McapFile> strict;
    try {
        strict = parseMcap(bytes, "fuzz", McapReadMode::Strict);
    } catch (const bop::Error&) {
    }
    std::optional<McapFile> tolerant;
    try {
        tolerant = parseMcap(bytes, "fuzz", McapReadMode::Tolerant);
    } catch (const bop::Error& e) {
        if (strict) fail(std::string("Strict accepts the file, Tolerant refuses it: ") + e.what());
        return;
    }
    if (strict) {
        if (!strict->complete) fail("Strict returned a file with complete == false");
        if (strict->validBytes != size) fail("Strict: validBytes != file size");
        if (!sameFile(*strict, *tolerant)) fail("Strict and Tolerant read the same complete file differently");
    }
    if (tolerant->validBytes > size) fail("Tolerant: validBytes beyond the end of the input");
    if (tolerant->complete && tolerant->validBytes != size) fail("Tolerant: complete but validBytes != size");
    // Reading only the complete records must give the same result (the cut is where they end).
    if (tolerant->validBytes < size) {
        McapFile again;
        try {
            again = parseMcap(bytes.first(std::size_t(tolerant->validBytes)), "fuzz", McapReadMode::Tolerant);
        } catch (const bop::Error& e) {
            fail(std::string("Tolerant refuses the first validBytes bytes of a file it accepted: ") + e.what());
        }
        if (!sameFile(again, *tolerant)) fail("Tolerant reads the first validBytes bytes differently");
    }
}

// bop-igtl's reader (protocol/igtl/IgtlWire.hpp) on the input as a stream of OpenIGTLink messages,
// as its server reads a connection: a header, then its body, and so on until the input ends or a
// header is refused. A refusal names its reason; a TRANSFORM read is 12 finite numbers that
// encode and read back to themselves.
void checkIgtl(const std::uint8_t* data, std::size_t size) {
    using namespace bop::igtl;
    const Misaligned odd(data, size);
    std::span<const std::uint8_t> in(odd.data, size);
    while (in.size() >= kHeaderSize) {
        Header h;
        std::string error;
        if (!readHeader(in.first<kHeaderSize>(), h, error)) {
            if (error.empty()) fail("readHeader refused a header without a reason");
            return;
        }
        in = in.subspan(kHeaderSize);
        if (h.bodySize > kMaxBodyBytes) fail("readHeader accepted a body over the limit");
        if (in.size() < h.bodySize) return;  // the rest of the body has not come
        const std::span<const std::uint8_t> body = in.first(std::size_t(h.bodySize));
        in = in.subspan(std::size_t(h.bodySize));
        std::span<const std::uint8_t> content;
        if (!readContent(h, body, content, error)) {
            if (error.empty()) fail("readContent refused a body without a reason");
            continue;
        }
        if (content.data() < body.data() || content.data() + content.size() > body.data() + body.size())
            fail("readContent's content lies outside the body");
        if (h.type != "TRANSFORM") continue;
        Eigen::Matrix4d t;
        if (!readTransform(content, t, error)) {
            if (error.empty()) fail("readTransform refused without a reason");
            continue;
        }
        if (!t.allFinite()) fail("readTransform accepted a value that is not finite");
        const std::vector<std::uint8_t> again = encodeMessage("TRANSFORM", h.device, transformBody(t));
        Header h2;
        std::span<const std::uint8_t> c2;
        Eigen::Matrix4d t2;
        if (!readHeader(std::span<const std::uint8_t, kHeaderSize>(again.data(), kHeaderSize), h2, error) ||
            !readContent(h2, std::span(again).subspan(kHeaderSize), c2, error) || !readTransform(c2, t2, error))
            fail("a TRANSFORM read does not read back once encoded: " + error);
        if (t2 != t) fail("a TRANSFORM read back to different numbers");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if constexpr (kTarget == "hello") {
        checkDecoder<Hello>(data, size, &decodeHello, &encodeHello, validator<Hello>());
    } else if constexpr (kTarget == "scene") {
        checkDecoder<SceneInfo>(data, size, &decodeSceneInfo, &encodeSceneInfo, validator<SceneInfo>());
    } else if constexpr (kTarget == "probe") {
        checkDecoder<Probe>(data, size, &decodeProbe, &encodeProbe, validator<Probe>());
    } else if constexpr (kTarget == "feedback") {
        checkDecoder<Feedback>(data, size, &decodeFeedback, &encodeFeedback, validator<Feedback>());
    } else if constexpr (kTarget == "command") {
        checkDecoder<Command>(data, size, &decodeCommand, &encodeCommand, validator<Command>());
    } else if constexpr (kTarget == "reply") {
        checkDecoder<CommandReply>(data, size, &decodeCommandReply, &encodeCommandReply, validator<CommandReply>());
    } else if constexpr (kTarget == "maprequest") {
        checkDecoder<MapRequest>(data, size, &decodeMapRequest, &encodeMapRequest, validator<MapRequest>());
    } else if constexpr (kTarget == "mapchunk") {
        checkDecoder<MapChunk>(data, size, &decodeMapChunk, &encodeMapChunk, validator<MapChunk>());
    } else if constexpr (kTarget == "mapedits") {
        checkDecoder<MapEdits>(data, size, &decodeMapEdits, &encodeMapEdits, validator<MapEdits>());
    } else if constexpr (kTarget == "refusal") {
        checkDecoder<Refusal>(data, size, &decodeRefusal, &encodeRefusal, validator<Refusal>());
    } else if constexpr (kTarget == "frame") {
        checkFrame(data, size);
    } else if constexpr (kTarget == "mcap") {
        checkMcap(data, size);
    } else if constexpr (kTarget == "igtl") {
        checkIgtl(data, size);
    }
    return 0;
}
