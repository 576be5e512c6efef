#include "recording/McapChunkCheck.hpp"

#include <zstd.h>

#include <algorithm>

namespace bop::recording::mcap {

ChunkContent readChunk(Fields& f) {
    ChunkContent c;
    c.startNs = f.u64("message_start_time");
    c.endNs = f.u64("message_end_time");
    const std::uint64_t size = f.u64("uncompressed_size");
    const std::uint32_t crc = f.u32("uncompressed_crc");
    c.compression = f.string("compression");
    const auto stored = f.bytes(f.u64("records length"), "records");
    c.compressedSize = stored.size();
    if (size > kMaxChunkBytes)
        f.fail("uncompressed_size " + std::to_string(size) + " is more than the " + std::to_string(kMaxChunkBytes) +
               " bytes this reader accepts in one chunk");
    if (c.compression.empty()) {
        if (stored.size() != size)
            f.fail("uncompressed_size " + std::to_string(size) + " but " + std::to_string(stored.size()) +
                   " bytes of uncompressed records");
        c.records.assign(stored.begin(), stored.end());
    } else if (c.compression == "zstd") {
        const unsigned long long framed = ZSTD_getFrameContentSize(stored.data(), stored.size());
        if (framed == ZSTD_CONTENTSIZE_ERROR) f.fail("zstd cannot decompress the records: they are not a zstd frame");
        if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed != size)
            f.fail("the zstd frame holds " + std::to_string(framed) + " bytes, uncompressed_size says " +
                   std::to_string(size));
        c.records.resize(size);
        const std::size_t n = ZSTD_decompress(c.records.data(), c.records.size(), stored.data(), stored.size());
        if (ZSTD_isError(n)) f.fail(std::string("zstd cannot decompress the records: ") + ZSTD_getErrorName(n));
        if (n != size)
            f.fail("decompressed to " + std::to_string(n) + " bytes, uncompressed_size says " + std::to_string(size));
    } else {
        f.fail("compression '" + c.compression + "' is not supported (expected zstd or none; " +
               "bop-replay export rewrites a recording with zstd)");
    }
    if (crc != 0 && crc32Update(0, c.records.data(), c.records.size()) != crc)
        f.fail("uncompressed CRC mismatch (the chunk is corrupted)");
    return c;
}

void ChunkIndexCheck::chunk(std::uint64_t pos, std::uint64_t length, const ChunkContent& c) {
    Chunk& k = chunks_[pos];
    k.length = length;
    k.compressedSize = c.compressedSize;
    k.uncompressedSize = c.records.size();
    k.startNs = c.startNs;
    k.endNs = c.endNs;
    k.compression = c.compression;
    last_ = &k;
    lastPos_ = pos;
}

void ChunkIndexCheck::message(std::uint64_t offsetInChunk, std::uint16_t channel, std::uint64_t logTimeNs) {
    last_->messages[channel].emplace_back(logTimeNs, offsetInChunk);
}

void ChunkIndexCheck::messageIndex(std::uint64_t pos, Fields& f) {
    const std::uint16_t channel = f.u16("channel_id");
    Fields entries = f.map("records");
    if (last_ == nullptr) f.fail("a MessageIndex record before any Chunk");
    std::vector<std::pair<std::uint64_t, std::uint64_t>> listed;
    while (!entries.empty()) {
        const std::uint64_t time = entries.u64("log_time");
        listed.emplace_back(time, entries.u64("offset"));
    }
    // The spec lists the chunk's messages of the channel; order by time is allowed, so compare sets.
    auto want = last_->messages[channel];
    std::sort(want.begin(), want.end());
    std::sort(listed.begin(), listed.end());
    if (listed != want)
        f.fail("the index of channel " + std::to_string(channel) + " lists " + std::to_string(listed.size()) +
               " messages that do not match the chunk at offset " + std::to_string(lastPos_) + " (it holds " +
               std::to_string(want.size()) + " on that channel)");
    if (!last_->indexAt.emplace(channel, pos).second)
        f.fail("a second MessageIndex of channel " + std::to_string(channel) + " for one chunk");
}

void ChunkIndexCheck::chunkIndex(Fields& f) {
    const std::uint64_t startNs = f.u64("message_start_time"), endNs = f.u64("message_end_time");
    const std::uint64_t pos = f.u64("chunk_start_offset"), length = f.u64("chunk_length");
    std::map<std::uint16_t, std::uint64_t> indexAt;
    Fields m = f.map("message_index_offsets");
    while (!m.empty()) {
        const std::uint16_t channel = m.u16("channel id");
        if (!indexAt.emplace(channel, m.u64("offset")).second)
            m.fail("duplicate channel id " + std::to_string(channel));
    }
    f.u64("message_index_length");
    const std::string compression = f.string("compression");
    const std::uint64_t compressed = f.u64("compressed_size"), uncompressed = f.u64("uncompressed_size");
    const auto it = chunks_.find(pos);
    if (it == chunks_.end()) f.fail("chunk_start_offset " + std::to_string(pos) + " is not the start of a Chunk");
    Chunk& k = it->second;
    if (k.indexed) f.fail("a second ChunkIndex for the chunk at offset " + std::to_string(pos));
    if (length != k.length || compression != k.compression || compressed != k.compressedSize ||
        uncompressed != k.uncompressedSize || startNs != k.startNs || endNs != k.endNs)
        f.fail("its length, compression, sizes or times differ from those of the chunk at offset " +
               std::to_string(pos));
    if (indexAt != k.indexAt)
        f.fail("message_index_offsets do not name the MessageIndex records after the chunk at offset " +
               std::to_string(pos));
    for (const auto& [channel, messages] : k.messages)
        if (!messages.empty() && !indexAt.count(channel))
            f.fail("the chunk at offset " + std::to_string(pos) + " has messages on channel " +
                   std::to_string(channel) + " and no MessageIndex for them");
    k.indexed = true;
    ++indexed_;
}

}  // namespace bop::recording::mcap
