#include "recording/McapChunk.hpp"

#include <zstd.h>

#include <algorithm>

namespace bop::recording {

using namespace mcap;

const char* mcapCompressionName(McapCompression c) {
    return c == McapCompression::Zstd ? "zstd" : "";
}

void McapChunk::add(std::uint16_t channelId, std::uint64_t logTimeNs, const Bytes& messageRecord) {
    startNs_ = records_.empty() ? logTimeNs : std::min(startNs_, logTimeNs);
    endNs_ = records_.empty() ? logTimeNs : std::max(endNs_, logTimeNs);
    index_[channelId].emplace_back(logTimeNs, records_.size());
    append(records_, messageRecord);
}

namespace {

Bytes compressZstd(const Bytes& in, int level, const std::string& where) {
    Bytes out(ZSTD_compressBound(in.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), in.data(), in.size(), level);
    if (ZSTD_isError(n)) throw Error(where, std::string("zstd cannot compress a chunk: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
}

}  // namespace

SealedChunk McapChunk::seal(std::uint64_t chunkStart, McapCompression compression, int level,
                            const std::string& where) {
    const Bytes stored = compression == McapCompression::Zstd ? compressZstd(records_, level, where) : records_;
    // Chunk: start and end log time, uncompressed size and CRC-32, compression, u64-prefixed records.
    Bytes chunk;
    putU64(chunk, startNs_);
    putU64(chunk, endNs_);
    putU64(chunk, records_.size());
    putU32(chunk, crc32Update(0, records_.data(), records_.size()));
    putString(chunk, mcapCompressionName(compression), where, "chunk compression");
    putU64(chunk, stored.size());
    append(chunk, stored);

    SealedChunk out;
    out.dataRecords = makeRecord(kChunk, chunk);
    const std::uint64_t chunkLength = out.dataRecords.size();
    // MessageIndex per channel: channel id, then u32-prefixed (log time, record offset) pairs.
    Bytes offsets;  // ChunkIndex's Map<channel id u16, MessageIndex record offset u64>
    for (const auto& [channel, entries] : index_) {
        putU16(offsets, channel);
        putU64(offsets, chunkStart + out.dataRecords.size());
        Bytes index;
        putU16(index, channel);
        putU32(index, u32Length(entries.size() * 16, where, "message index"));
        for (const auto& [time, offset] : entries) {
            putU64(index, time);
            putU64(index, offset);
        }
        append(out.dataRecords, makeRecord(kMessageIndex, index));
    }
    Bytes ci;
    putU64(ci, startNs_);
    putU64(ci, endNs_);
    putU64(ci, chunkStart);
    putU64(ci, chunkLength);
    putU32(ci, u32Length(offsets.size(), where, "message index offsets"));
    append(ci, offsets);
    putU64(ci, out.dataRecords.size() - chunkLength);  // message_index_length
    putString(ci, mcapCompressionName(compression), where, "chunk compression");
    putU64(ci, stored.size());
    putU64(ci, records_.size());
    out.chunkIndex = makeRecord(kChunkIndex, ci);

    records_.clear();
    index_.clear();
    return out;
}

}  // namespace bop::recording
