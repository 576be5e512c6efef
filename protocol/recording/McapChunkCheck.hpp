#pragma once
// Reading MCAP chunks and checking their indexes (https://mcap.dev/spec "Chunk", "Message Index",
// "Chunk Index"), for McapReader; internal to recording/. Chunks come from untrusted files: sizes
// are bounded before anything is allocated, and every index entry must point at what it claims.
#include "recording/McapFields.hpp"

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace bop::recording::mcap {

// Largest uncompressed chunk accepted, bytes (writers use about 1 MiB; bounds a decompression bomb).
inline constexpr std::uint64_t kMaxChunkBytes = std::uint64_t(256) << 20;

// A Chunk record's fields; records holds the uncompressed Schema, Channel and Message records.
struct ChunkContent {
    std::uint64_t startNs = 0, endNs = 0;  // message start and end log time, ns
    std::string compression;               // "" or "zstd"
    std::uint64_t compressedSize = 0;
    std::vector<std::uint8_t> records;
};

// Reads a Chunk record's content: decompresses it (zstd or none; lz4 and others are refused) and
// checks its size and CRC-32 against what the record states. Errors through f.fail.
ChunkContent readChunk(Fields& f);

// Every chunk's messages as read, so the MessageIndex records after a chunk and the ChunkIndex
// records of the summary can be checked against them.
class ChunkIndexCheck {
public:
    // A chunk at file offset pos, length bytes in all (record prefix included).
    void chunk(std::uint64_t pos, std::uint64_t length, const ChunkContent& c);
    // A message of the last chunk: its record's offset in the uncompressed records.
    void message(std::uint64_t offsetInChunk, std::uint16_t channel, std::uint64_t logTimeNs);
    // A MessageIndex record at pos: must follow a chunk and list exactly its messages of the channel.
    void messageIndex(std::uint64_t pos, Fields& f);
    // A ChunkIndex record of the summary: must match its chunk and point at its MessageIndex records.
    void chunkIndex(Fields& f);
    std::size_t chunks() const { return chunks_.size(); }
    std::size_t indexed() const { return indexed_; }

private:
    struct Chunk {
        std::uint64_t length = 0, compressedSize = 0, uncompressedSize = 0, startNs = 0, endNs = 0;
        std::string compression;
        // Messages by channel: (log time, record offset in the uncompressed records), file order.
        std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> messages;
        std::map<std::uint16_t, std::uint64_t> indexAt;  // channel -> offset of its MessageIndex record
        bool indexed = false;
    };
    std::map<std::uint64_t, Chunk> chunks_;  // by file offset
    Chunk* last_ = nullptr;                  // the chunk MessageIndex records refer to
    std::uint64_t lastPos_ = 0;
    std::size_t indexed_ = 0;
};

}  // namespace bop::recording::mcap
