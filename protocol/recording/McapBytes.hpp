#pragma once
// Building MCAP record content (https://mcap.dev/spec): little-endian integers, u32-length-prefixed
// strings and maps, whole records. Internal to recording/ (McapWriter and McapChunk).
#include "bop/common/Error.hpp"
#include "recording/McapFormat.hpp"

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace bop::recording::mcap {

using Bytes = std::vector<std::uint8_t>;

inline void putLe(Bytes& out, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
inline void putU8(Bytes& out, std::uint8_t v) {
    out.push_back(v);
}
inline void putU16(Bytes& out, std::uint16_t v) {
    putLe(out, v, 2);
}
inline void putU32(Bytes& out, std::uint32_t v) {
    putLe(out, v, 4);
}
inline void putU64(Bytes& out, std::uint64_t v) {
    putLe(out, v, 8);
}
inline void append(Bytes& out, const Bytes& more) {
    out.insert(out.end(), more.begin(), more.end());
}

// MCAP prefixes strings, byte arrays and maps with a u32 byte length.
inline std::uint32_t u32Length(std::size_t n, const std::string& where, const std::string& field) {
    if (n > std::numeric_limits<std::uint32_t>::max())
        throw Error(where, field + " is " + std::to_string(n) + " bytes; MCAP allows at most 4 GiB - 1");
    return static_cast<std::uint32_t>(n);
}

inline void putString(Bytes& out, const std::string& s, const std::string& where, const std::string& field) {
    putU32(out, u32Length(s.size(), where, field));
    out.insert(out.end(), s.begin(), s.end());
}

// Map<string, string>: u32 byte length of all entries, then key and value strings in key order.
inline void putStringMap(Bytes& out, const std::map<std::string, std::string>& map, const std::string& where) {
    Bytes entries;
    for (const auto& [key, value] : map) {
        putString(entries, key, where, "channel metadata key");
        putString(entries, value, where, "channel metadata value '" + key + "'");
    }
    putU32(out, u32Length(entries.size(), where, "channel metadata"));
    append(out, entries);
}

// A whole record: opcode, u64 content length, content.
inline Bytes makeRecord(std::uint8_t op, const Bytes& content) {
    Bytes r;
    r.reserve(kRecordPrefix + content.size());
    putU8(r, op);
    putU64(r, content.size());
    append(r, content);
    return r;
}

}  // namespace bop::recording::mcap
