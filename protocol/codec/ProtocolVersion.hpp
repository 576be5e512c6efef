#pragma once
// Version of the BoP wire protocol (schemas in protocol/schemas/*.fbs). Tables only gain fields
// at their end, so a reader of any version reads a buffer of any other: fields it does not know
// are skipped, fields the writer did not know read their schema defaults. The version is sent in
// Hello and SceneInfo so that each side can tell what the other may leave out.
#include <cstdint>

namespace bop::protocol {

inline constexpr std::uint16_t kProtocolVersion = 1;

}  // namespace bop::protocol
