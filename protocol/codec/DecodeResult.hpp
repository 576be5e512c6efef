#pragma once
// What a decoder returns, why it may refuse a buffer, and the size caps it checks first.
// Decoders never throw on bad input: they return the first reason found with a message that
// names the message type and field.
#include <cstddef>
#include <cstdint>
#include <string>

namespace bop::protocol {

enum class DecodeError : std::uint8_t {
    None = 0,
    TooShort,         // fewer bytes than a root offset and a file identifier (8)
    TooLarge,         // more bytes than the message's cap; rejected before verification
    WrongIdentifier,  // the file identifier names another message (or none)
    Malformed,        // the FlatBuffers verifier refused it (offsets, bounds, depth, table count)
    MissingField,     // a field the message needs is absent
    BadLength,        // arrays or strings of the wrong length (positions != 3 x count, ...)
    NotFinite,        // NaN or infinity where a number is needed
    OutOfRange,       // a value outside its domain (species number, chunk index, k0 <= 0, ...)
    Unsupported,      // an enum value or command this version does not know
};

const char* toString(DecodeError e);

// A refusal for a value (outside its valid range, or not finite) rather than for the buffer.
inline bool valueRefused(DecodeError e) {
    return e == DecodeError::NotFinite || e == DecodeError::OutOfRange;
}

template <class T>
struct Decoded {
    T value{};  // meaningful when ok() or read
    DecodeError error = DecodeError::None;
    std::string message;  // empty when ok()
    // The buffer was whole and its fields were read, but a value broke a rule (validate()):
    // `value` holds what was read, so that a receiver can name what it refuses (a command's
    // request id, a probe's sequence). Never apply such a value.
    bool read = false;

    bool ok() const { return error == DecodeError::None; }
    explicit operator bool() const { return ok(); }
};

// Byte caps per message, checked before anything else is read. A message built from valid
// values stays far below its cap (tests/protocol check the largest ones).
inline constexpr std::size_t kMaxHelloBytes = 4 * 1024;
inline constexpr std::size_t kMaxSceneInfoBytes = 64 * 1024;  // 255 species with 64-byte names fit
inline constexpr std::size_t kMaxProbeBytes = 256;
inline constexpr std::size_t kMaxFeedbackBytes = 256;
inline constexpr std::size_t kMaxCommandBytes = 4 * 1024;
inline constexpr std::size_t kMaxReplyBytes = 4 * 1024;
inline constexpr std::size_t kMaxMapRequestBytes = 256;
inline constexpr std::size_t kMaxRefusalBytes = 2 * 1024;
inline constexpr std::size_t kMaxMapPieceBytes = 1 << 20;                  // data of one MapChunk
inline constexpr std::size_t kMaxMapChunkBytes = kMaxMapPieceBytes + 256;  // the whole MapChunk
inline constexpr std::size_t kMaxMapEditsRequestBytes = 256;
inline constexpr std::size_t kMaxMapEditsBytes = kMaxMapChunkBytes;  // fits a client's control socket
inline constexpr std::size_t kMaxEditVoxels = 1 << 16;               // voxels of one MapEdit (a yield is split)
inline constexpr std::size_t kMaxEditsPerMessage = 4096;             // edits of one MapEdits
// The most one edit of `voxels` voxels takes in a MapEdits (its table, vector and offset, padded),
// bytes; a MapEdits holds edits of at most kMaxMapEditsPayload of them, so it stays within its cap.
inline constexpr std::size_t mapEditWireBytes(std::size_t voxels) {
    return 8 * voxels + 128;
}
inline constexpr std::size_t kMaxMapEditsPayload = kMaxMapEditsBytes - 1024;
inline constexpr std::size_t kDefaultMaxFrameChunkBytes = 8u << 20;
// FlatBuffers addresses less than 2 GiB; FrameLimits::maxChunkBytes is clamped to 1 GiB.
inline constexpr std::size_t kAbsoluteMaxBytes = std::size_t(1) << 30;
// Largest magnitude of a quantisation bound, length: decoded positions must fit a float32.
inline constexpr double kMaxBoundMagnitude = 1e30;

// String caps, bytes.
inline constexpr std::size_t kMaxNameBytes = 64;       // client, species and parameter names
inline constexpr std::size_t kMaxEndpointBytes = 256;  // ZeroMQ endpoint strings
inline constexpr std::size_t kMaxPathBytes = 1024;     // checkpoint and recording paths
inline constexpr std::size_t kMaxTextBytes = 1024;     // units text, reply messages

inline constexpr int kMaxSpecies = 255;  // species numbers travel as uint8

// Limits of a frame-chunk decoder, chosen by the receiver.
struct FrameLimits {
    std::size_t maxChunkBytes = kDefaultMaxFrameChunkBytes;  // whole buffer, bytes
    std::uint32_t maxChunkCount = 4096;                      // chunks per frame
    int speciesCount = 0;  // species numbers above it are refused; 0 = not known (1..255 accepted)
};

}  // namespace bop::protocol
