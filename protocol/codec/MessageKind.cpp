// Message kinds by file identifier, and names of decode errors.
#include "codec/MessageKind.hpp"

#include "codec/DecodeResult.hpp"

#include <array>
#include <cstring>

namespace bop::protocol {

namespace {

struct KindEntry {
    MessageKind kind;
    const char* identifier;
    const char* name;
};

// Identifiers must match the file_identifier of each schema in protocol/schemas/.
constexpr std::array<KindEntry, 12> kKinds{{
    {MessageKind::Hello, "BHEL", "Hello"},
    {MessageKind::SceneInfo, "BSCN", "SceneInfo"},
    {MessageKind::StateFrame, "BFRM", "StateFrame"},
    {MessageKind::Probe, "BPRB", "Probe"},
    {MessageKind::Feedback, "BFBK", "Feedback"},
    {MessageKind::Command, "BCMD", "Command"},
    {MessageKind::CommandReply, "BRPL", "CommandReply"},
    {MessageKind::MapRequest, "BMRQ", "MapRequest"},
    {MessageKind::MapChunk, "BMCK", "MapChunk"},
    {MessageKind::Refusal, "BREF", "Refusal"},
    {MessageKind::MapEditsRequest, "BMER", "MapEditsRequest"},
    {MessageKind::MapEdits, "BMED", "MapEdits"},
}};

}  // namespace

MessageKind messageKind(const std::uint8_t* buf, std::size_t len) {
    // Bytes 0..3 are the root offset, 4..7 the identifier.
    if (buf == nullptr || len < 8) return MessageKind::Unknown;
    for (const KindEntry& k : kKinds)
        if (std::memcmp(buf + 4, k.identifier, 4) == 0) return k.kind;
    return MessageKind::Unknown;
}

const char* fileIdentifier(MessageKind kind) {
    for (const KindEntry& k : kKinds)
        if (k.kind == kind) return k.identifier;
    return "";
}

const char* toString(MessageKind kind) {
    for (const KindEntry& k : kKinds)
        if (k.kind == kind) return k.name;
    return "an unknown message";
}

const char* toString(DecodeError e) {
    switch (e) {
        case DecodeError::None:
            return "none";
        case DecodeError::TooShort:
            return "too short";
        case DecodeError::TooLarge:
            return "too large";
        case DecodeError::WrongIdentifier:
            return "wrong identifier";
        case DecodeError::Malformed:
            return "malformed";
        case DecodeError::MissingField:
            return "missing field";
        case DecodeError::BadLength:
            return "bad length";
        case DecodeError::NotFinite:
            return "not finite";
        case DecodeError::OutOfRange:
            return "out of range";
        case DecodeError::Unsupported:
            return "unsupported";
    }
    return "unknown error";
}

}  // namespace bop::protocol
