#pragma once
// One MCAP chunk being filled (https://mcap.dev/spec "Chunk", "Message Index", "Chunk Index"):
// Message records collected uncompressed, then sealed into the bytes that go into the data section
// (the Chunk record, compressed, followed by one MessageIndex record per channel in it) and the
// ChunkIndex record that goes into the summary. Internal to recording/ (McapWriter).
#include "recording/McapBytes.hpp"

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bop::recording {

// How chunk records are compressed. Zstd uses Debian's libzstd; None stores them as they are.
enum class McapCompression { None, Zstd };

// The MCAP name of a compression ("" or "zstd").
const char* mcapCompressionName(McapCompression c);

struct SealedChunk {
    mcap::Bytes dataRecords;  // Chunk record, then its MessageIndex records, back to back
    mcap::Bytes chunkIndex;   // the ChunkIndex record for the summary
};

class McapChunk {
public:
    // Adds a whole Message record (opcode, length, content) of channelId logged at logTimeNs.
    void add(std::uint16_t channelId, std::uint64_t logTimeNs, const mcap::Bytes& messageRecord);
    bool empty() const { return records_.empty(); }
    std::size_t bytes() const { return records_.size(); }  // uncompressed

    // Seals the chunk as it will sit at file offset chunkStart and empties it for the next one.
    // level: zstd compression level (1 fast .. 19 small). where names the file in errors.
    SealedChunk seal(std::uint64_t chunkStart, McapCompression compression, int level, const std::string& where);

private:
    mcap::Bytes records_;
    std::uint64_t startNs_ = 0, endNs_ = 0;  // earliest and latest log time in the chunk, ns
    // Per channel: (log time ns, offset of the Message record in the uncompressed records).
    std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index_;
};

}  // namespace bop::recording
