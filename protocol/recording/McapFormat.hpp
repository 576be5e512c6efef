#pragma once
// Constants of the MCAP container format (https://mcap.dev/spec, major version "0") shared by
// McapWriter and McapReader. All integers in MCAP are little-endian; a record is
// <opcode u8><content length u64><content>, so every record has kRecordPrefix bytes before its content.
#include <zlib.h>

#include <array>
#include <cstddef>
#include <cstdint>

namespace bop::recording::mcap {

// First and last 8 bytes of every MCAP file: 0x89 "MCAP" '0' (major version) "\r\n".
inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

// Record opcodes from the spec (0x01-0x7F reserved for MCAP, 0x80-0xFF for applications).
enum Op : std::uint8_t {
    kHeader = 0x01,
    kFooter = 0x02,
    kSchema = 0x03,
    kChannel = 0x04,
    kMessage = 0x05,
    kChunk = 0x06,
    kMessageIndex = 0x07,
    kChunkIndex = 0x08,
    kAttachment = 0x09,
    kAttachmentIndex = 0x0A,
    kStatistics = 0x0B,
    kMetadata = 0x0C,
    kMetadataIndex = 0x0D,
    kSummaryOffset = 0x0E,
    kDataEnd = 0x0F,
};

inline constexpr std::uint64_t kRecordPrefix = 1 + 8;  // opcode + content length
// Fixed content sizes: Footer (summary_start u64, summary_offset_start u64, summary_crc u32) and
// the fixed part of a Message (channel_id u16, sequence u32, log_time u64, publish_time u64).
inline constexpr std::uint64_t kFooterContent = 8 + 8 + 4;
inline constexpr std::uint64_t kMessageFixed = 2 + 4 + 8 + 8;

// Continues a zlib CRC-32 (the one MCAP uses; start with crc = 0) over n bytes. zlib's crc32()
// takes a 32-bit length, so large spans are fed in 1 GiB pieces.
inline std::uint32_t crc32Update(std::uint32_t crc, const std::uint8_t* p, std::size_t n) {
    constexpr std::size_t kPiece = std::size_t(1) << 30;
    uLong c = crc;
    while (n > 0) {
        const std::size_t k = n < kPiece ? n : kPiece;
        c = ::crc32(c, p, static_cast<uInt>(k));
        p += k;
        n -= k;
    }
    return static_cast<std::uint32_t>(c);
}

}  // namespace bop::recording::mcap
