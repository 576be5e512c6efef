#pragma once
// Bounds-checked reading of MCAP record content, used by McapReader (internal to recording/).
// Fields never reads past the content it was given: each length is checked against the bytes that
// remain before use, and a failure throws bop::Error naming the record kind and its file offset.
#include "bop/common/Error.hpp"
#include "recording/McapFormat.hpp"

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>

namespace bop::recording::mcap {

inline std::uint64_t loadLe(const std::uint8_t* p, int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t(p[i]) << (8 * i);
    return v;
}

inline bool isMagic(std::span<const std::uint8_t> b, std::uint64_t at) {
    return b.size() >= at + 8 && std::equal(kMagic.begin(), kMagic.end(), b.begin() + at);
}

inline const char* opName(std::uint8_t op) {
    static const char* const names[] = {"Invalid",    "Header",        "Footer",          "Schema",
                                        "Channel",    "Message",       "Chunk",           "MessageIndex",
                                        "ChunkIndex", "Attachment",    "AttachmentIndex", "Statistics",
                                        "Metadata",   "MetadataIndex", "SummaryOffset",   "DataEnd"};
    return op <= kDataEnd ? names[op] : "unknown";  // unknown opcodes are skipped, not errors
}

// Fields of one record's content, read front to back; nothing past the content's end is touched.
// The error context (record kind and file offset) is only formatted when something fails.
class Fields {
public:
    Fields(std::span<const std::uint8_t> content, const std::string& where, std::uint8_t op, std::uint64_t pos,
           const char* within = nullptr)
        : rest_(content), where_(where), op_(op), pos_(pos), within_(within) {}

    std::uint16_t u16(const char* field) { return static_cast<std::uint16_t>(take(2, field)); }
    std::uint32_t u32(const char* field) { return static_cast<std::uint32_t>(take(4, field)); }
    std::uint64_t u64(const char* field) { return take(8, field); }

    std::span<const std::uint8_t> bytes(std::uint64_t n, const char* field) {
        if (n > rest_.size())
            fail(std::string(field) + " claims " + std::to_string(n) + " bytes but only " +
                 std::to_string(rest_.size()) + " remain in the record");
        const auto out = rest_.first(static_cast<std::size_t>(n));
        rest_ = rest_.subspan(static_cast<std::size_t>(n));
        return out;
    }
    std::string string(const char* field) {  // u32 byte length, then UTF-8 bytes
        const auto b = bytes(u32(field), field);
        return std::string(b.begin(), b.end());
    }
    Fields map(const char* field) {  // u32 byte length, then entries parsed from the returned Fields
        return Fields(bytes(u32(field), field), where_, op_, pos_, field);
    }
    std::span<const std::uint8_t> rest() { return bytes(rest_.size(), "data"); }
    bool empty() const { return rest_.empty(); }

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(where_, std::string(opName(op_)) + " record (opcode " + std::to_string(op_) + ") at offset " +
                                std::to_string(pos_) + (within_ ? std::string(", ") + within_ : "") + ": " + what);
    }

private:
    std::uint64_t take(int n, const char* field) {
        return loadLe(bytes(static_cast<std::uint64_t>(n), field).data(), n);
    }
    std::span<const std::uint8_t> rest_;
    const std::string& where_;
    std::uint8_t op_;
    std::uint64_t pos_;
    const char* within_;  // the map being read, if any
};

}  // namespace bop::recording::mcap
