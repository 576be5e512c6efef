#pragma once
// Encoders and decoders of every wire message (schemas/*.fbs <-> codec/Messages.hpp).
//
// Decoders take untrusted bytes and, in this order: refuse more bytes than the message's cap
// (DecodeResult.hpp) or fewer than 8, check the file identifier, run the FlatBuffers verifier
// with depth and table-count limits, read the fields into the plain struct, and check it with
// validate() (Validate.hpp). They never throw on bad input and never read outside [buf, buf+len).
// A buffer not aligned to 8 bytes is copied once before it is verified.
//
// Encoders check their input with the same validate() and throw EncodeError on a value that a
// decoder would refuse, so a peer never receives a buffer this side knows to be bad.
#include "codec/DecodeResult.hpp"
#include "codec/Messages.hpp"
#include "codec/Validate.hpp"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace bop::protocol {

class BufferPool;

using Buffer = std::vector<std::uint8_t>;

class EncodeError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

Buffer encodeHello(const Hello& m);
Decoded<Hello> decodeHello(const std::uint8_t* buf, std::size_t len);

Buffer encodeSceneInfo(const SceneInfo& m);
Decoded<SceneInfo> decodeSceneInfo(const std::uint8_t* buf, std::size_t len);

Buffer encodeProbe(const Probe& m);
Decoded<Probe> decodeProbe(const std::uint8_t* buf, std::size_t len);

Buffer encodeFeedback(const Feedback& m);
Decoded<Feedback> decodeFeedback(const std::uint8_t* buf, std::size_t len);

Buffer encodeMapRequest(const MapRequest& m);
Decoded<MapRequest> decodeMapRequest(const std::uint8_t* buf, std::size_t len);

Buffer encodeMapChunk(const MapChunk& m);
Decoded<MapChunk> decodeMapChunk(const std::uint8_t* buf, std::size_t len);

Buffer encodeMapEditsRequest(const MapEditsRequest& m);
Decoded<MapEditsRequest> decodeMapEditsRequest(const std::uint8_t* buf, std::size_t len);

Buffer encodeMapEdits(const MapEdits& m);
Decoded<MapEdits> decodeMapEdits(const std::uint8_t* buf, std::size_t len);

Buffer encodeRefusal(const Refusal& m);
Decoded<Refusal> decodeRefusal(const std::uint8_t* buf, std::size_t len);

Buffer encodeCommand(const Command& m);
Decoded<Command> decodeCommand(const std::uint8_t* buf, std::size_t len);

Buffer encodeCommandReply(const CommandReply& m);
Decoded<CommandReply> decodeCommandReply(const std::uint8_t* buf, std::size_t len);

// One chunk as it is (chunkIndex, chunkCount, firstIndex taken from m). With Quantised16 the
// positions are quantised against [quantLo, quantHi] (clamped into it) and the normals
// octahedral-encoded (Quantise.hpp).
Buffer encodeStateFrame(const StateFrame& m);

// A whole frame (m.chunkIndex 0, m.chunkCount 1, m.firstIndex 0) split into as few chunks as keep
// every buffer within maxChunkBytes; each chunk repeats the header fields. Throws EncodeError if
// maxChunkBytes cannot hold the header and one particle, or the frame needs more chunks than a
// receiver accepts by default (FrameLimits::maxChunkCount).
// With a pool, the chunks are written into buffers taken from it (BufferPool.hpp).
std::vector<Buffer> encodeStateFrameChunks(const StateFrame& m, std::size_t maxChunkBytes = kDefaultMaxFrameChunkBytes,
                                           BufferPool* pool = nullptr);

// Quantised16 chunks come back as float32 arrays (dequantised), with encoding Quantised16.
Decoded<StateFrame> decodeStateFrame(const std::uint8_t* buf, std::size_t len, const FrameLimits& limits = {});
// The same into `out`, whose arrays keep their capacity: a receiver that decodes into the same
// frame again and again allocates no memory once the arrays are large enough. On failure `out`
// holds unspecified (but valid) contents.
Validation decodeStateFrameInto(const std::uint8_t* buf, std::size_t len, StateFrame& out,
                                const FrameLimits& limits = {});

}  // namespace bop::protocol
