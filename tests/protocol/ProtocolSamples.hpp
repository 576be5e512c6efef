#pragma once
// Sample messages for the protocol tests, value comparisons, and a decoder that dispatches on
// the message kind (for tests that run over every message).
#include "codec/Codec.hpp"
#include "codec/MessageKind.hpp"

#include <cstdint>
#include <vector>

namespace bop::protocol::samples {

Hello sampleHello();
SceneInfo sampleScene(int speciesCount = 4);
Probe sampleProbe();
Feedback sampleFeedback();
std::vector<Command> sampleCommands();  // one of each body type
CommandReply sampleReply();
MapRequest sampleMapRequest();
MapChunk sampleMapChunk();
MapEditsRequest sampleMapEditsRequest();
MapEdits sampleMapEdits();  // a blade and a yield
Refusal sampleRefusal();
// n particles inside the box [-10, 20] x [0, 5] x [-3, 3], unit normals, species 1..4, ids when
// asked; frameParticleCount = n (one whole chunk).
StateFrame sampleFrame(std::size_t n, FrameEncoding encoding, bool withNormals, bool withIds, std::uint32_t seed = 7);

bool same(const Hello& a, const Hello& b);
bool same(const SceneInfo& a, const SceneInfo& b);
bool same(const Probe& a, const Probe& b);
bool same(const Feedback& a, const Feedback& b);
bool same(const Command& a, const Command& b);
bool same(const CommandReply& a, const CommandReply& b);
bool same(const LoopStats& a, const LoopStats& b);
bool same(const MapRequest& a, const MapRequest& b);
bool same(const MapChunk& a, const MapChunk& b);
bool same(const MapEditsRequest& a, const MapEditsRequest& b);
bool same(const MapEdits& a, const MapEdits& b);
bool same(const Refusal& a, const Refusal& b);
bool same(const StateFrame& a, const StateFrame& b);  // exact, arrays included

struct Sample {
    MessageKind kind;
    Buffer bytes;
};
// One encoded buffer of every message type (each command body, float and quantised frames).
std::vector<Sample> allSamples();

// Decodes `len` bytes as `kind` (frames with speciesCount 4). When the decoder accepts them, the
// value is re-encoded and decoded again; `stable` says the second value equals the first (so
// whatever is accepted is a value the encoder considers valid).
struct DecodeCheck {
    DecodeError error = DecodeError::None;
    bool stable = false;
};
DecodeCheck decodeAs(MessageKind kind, const std::uint8_t* buf, std::size_t len);

// Decodes a valid buffer and compares the value with the decoded original buffer.
bool decodesToSameAs(MessageKind kind, const std::uint8_t* buf, std::size_t len, const Buffer& original);

}  // namespace bop::protocol::samples
