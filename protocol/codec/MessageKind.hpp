#pragma once
// Which message a buffer holds, from its 4-byte file identifier (bytes 4..7 of every buffer).
// A transport that multiplexes messages peeks the kind, then calls that message's decoder, which
// verifies the whole buffer.
#include <cstddef>
#include <cstdint>

namespace bop::protocol {

enum class MessageKind : std::uint8_t {
    Unknown = 0,
    Hello,            // "BHEL"
    SceneInfo,        // "BSCN"
    StateFrame,       // "BFRM"
    Probe,            // "BPRB"
    Feedback,         // "BFBK"
    Command,          // "BCMD"
    CommandReply,     // "BRPL"
    MapRequest,       // "BMRQ"
    MapChunk,         // "BMCK"
    Refusal,          // "BREF"
    MapEditsRequest,  // "BMER"
    MapEdits,         // "BMED"
};

// Unknown when buf is null, shorter than 8 bytes, or its identifier is none of the above.
// Reads at most bytes 4..7; does not verify the buffer.
MessageKind messageKind(const std::uint8_t* buf, std::size_t len);

// The file identifier of a kind (4 characters, NUL-terminated); "" for Unknown.
const char* fileIdentifier(MessageKind kind);
const char* toString(MessageKind kind);

}  // namespace bop::protocol
