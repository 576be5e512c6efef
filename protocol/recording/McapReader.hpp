#pragma once
// Reads MCAP files (https://mcap.dev/spec, major version "0") such as McapWriter produces, from
// untrusted bytes: every length is checked against the bytes that are really there before use.
// Whole files are read into memory (at most maxFileBytes). Supported: Schema, Channel and Message
// records in the data section, unchunked or in Chunk records (uncompressed or zstd; lz4 is refused
// with an error, never skipped, since skipping would silently lose messages; at most 256 MiB
// uncompressed per chunk), DataEnd (CRC checked when nonzero), a summary with Schema/Channel
// copies (checked against the data section), Statistics and SummaryOffset, and the Footer's summary
// CRC (checked when nonzero). Indexes are checked, not used: each MessageIndex must list exactly
// its chunk's messages of its channel, each ChunkIndex must match its chunk and name its
// MessageIndex records, and a summary that indexes chunks must index them all. Records with other
// opcodes (attachment, metadata, application 0x80-0xFF, ...) are skipped as the spec allows.
// Trailing bytes inside a known record (fields added by later spec versions) are ignored.
// Errors: bop::Error(where, what), where = the path (or the name given to parseMcap), what
// includes the byte offset of the offending record.
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace bop::recording {

enum class McapReadMode {
    // A complete file: magic at both ends, Header first, DataEnd, Footer, nothing after the magic.
    Strict,
    // A file cut anywhere, e.g. McapWriter's PATH.partial after a crash: the result holds every
    // record that is complete; the first record whose header or content is cut short ends the
    // read without an error. A cut cannot be told from a corrupted length field, so a record whose
    // length runs past the end of the file is taken as the cut, and so is opcode 0 (invalid in
    // MCAP; file systems can leave zero bytes at the end of a file after a power loss). Complete
    // records are still checked (a malformed one, a wrong magic or a wrong DataEnd CRC is an error).
    Tolerant,
};

struct McapSchema {
    std::uint16_t id = 0;
    std::string name;
    std::string encoding;            // e.g. "flatbuffer"
    std::vector<std::uint8_t> data;  // e.g. a binary FlatBuffers reflection schema (.bfbs)
    bool operator==(const McapSchema&) const = default;
};

struct McapChannel {
    std::uint16_t id = 0;
    std::uint16_t schemaId = 0;  // 0: no schema
    std::string topic;
    std::string messageEncoding;  // e.g. "flatbuffer"
    std::map<std::string, std::string> metadata;
    bool operator==(const McapChannel&) const = default;
};

struct McapMessage {
    std::uint16_t channelId = 0;
    std::uint32_t sequence = 0;
    std::uint64_t logTimeNs = 0;      // nanoseconds, epoch chosen by the writer
    std::uint64_t publishTimeNs = 0;  // nanoseconds, same epoch
    std::vector<std::uint8_t> data;
    bool operator==(const McapMessage&) const = default;
};

struct McapStatistics {
    std::uint64_t messageCount = 0;
    std::uint16_t schemaCount = 0;
    std::uint32_t channelCount = 0;
    std::uint32_t attachmentCount = 0;
    std::uint32_t metadataCount = 0;
    std::uint32_t chunkCount = 0;
    std::uint64_t messageStartTimeNs = 0;                         // earliest log time (ns), 0 without messages
    std::uint64_t messageEndTimeNs = 0;                           // latest log time (ns), 0 without messages
    std::map<std::uint16_t, std::uint64_t> channelMessageCounts;  // channel id -> messages
    bool operator==(const McapStatistics&) const = default;
};

struct McapFile {
    std::string profile;
    std::string library;
    std::vector<McapSchema> schemas;    // in order of first appearance; ids are unique
    std::vector<McapChannel> channels;  // in order of first appearance; ids are unique
    std::vector<McapMessage> messages;  // in file order
    std::optional<McapStatistics> statistics;
    bool hasDataEnd = false;
    std::uint32_t dataSectionCrc = 0;  // as stored in DataEnd (0: not computed by the writer)
    bool complete = false;             // Footer and closing magic present (always true in Strict mode)
    std::uint64_t validBytes = 0;      // offset just past the last complete record (or magic)
    std::size_t chunkCount = 0;        // Chunk records (counted when the Footer is read)
    std::size_t indexedChunks = 0;     // of them, those the summary's ChunkIndex records point at

    const McapSchema* schema(std::uint16_t id) const;
    const McapChannel* channel(std::uint16_t id) const;
};

// Default cap on the file size (bytes) readMcap accepts, since the file is held in memory.
inline constexpr std::uint64_t kMcapDefaultMaxBytes = std::uint64_t(4) << 30;

// Reads and checks the file at path. Throws bop::Error(path, ...) if it cannot be read, is larger
// than maxFileBytes, or is not valid for the mode.
McapFile readMcap(const std::string& path, McapReadMode mode = McapReadMode::Strict,
                  std::uint64_t maxFileBytes = kMcapDefaultMaxBytes);

// Parses bytes already in memory; where names them in errors.
McapFile parseMcap(std::span<const std::uint8_t> bytes, const std::string& where,
                   McapReadMode mode = McapReadMode::Strict);

}  // namespace bop::recording
