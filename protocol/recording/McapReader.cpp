#include "recording/McapReader.hpp"

#include "bop/common/Error.hpp"
#include "recording/McapChunkCheck.hpp"
#include "recording/McapFields.hpp"
#include "recording/McapFormat.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace bop::recording {

namespace {

using mcap::Fields;
using mcap::isMagic;
using mcap::loadLe;

class Parser {
public:
    Parser(std::span<const std::uint8_t> b, const std::string& where, McapReadMode mode)
        : b_(b), where_(where), tolerant_(mode == McapReadMode::Tolerant) {}

    McapFile run() {
        if (b_.size() < 8 && tolerant_ && std::equal(b_.begin(), b_.end(), mcap::kMagic.begin()))
            return std::move(out_);  // cut inside the magic: nothing recorded yet
        if (!isMagic(b_, 0)) throw Error(where_, "not an MCAP file (the first 8 bytes are not the MCAP magic)");
        if (!tolerant_ && (b_.size() < 16 || !isMagic(b_, b_.size() - 8)))
            throw Error(where_,
                        "truncated: the file does not end with the MCAP magic (an unfinished recording"
                        " can be read in tolerant mode)");
        std::uint64_t pos = 8;
        out_.validBytes = pos;
        while (!out_.complete) {
            const std::uint64_t left = b_.size() - pos;
            const char* cut = left < mcap::kRecordPrefix ? "has no complete opcode and length"
                              : b_[pos] == 0 ? "has opcode 0 (invalid; zero bytes where a crash cut the file?)"
                              : loadLe(&b_[pos + 1], 8) > left - mcap::kRecordPrefix
                                  ? "is longer than the rest of the file"
                                  : nullptr;
            if (cut) {
                if (tolerant_) break;  // the cut: keep the complete records before it
                throw Error(where_, "truncated or corrupted: the record at offset " + std::to_string(pos) + " " + cut +
                                        " (expected a Footer before the end)");
            }
            const std::uint64_t len = loadLe(&b_[pos + 1], 8);
            const std::uint8_t op = b_[pos];
            Fields f(b_.subspan(pos + mcap::kRecordPrefix, len), where_, op, pos);
            recordEnd_ = pos + mcap::kRecordPrefix + len;
            record(op, pos, f);
            pos = recordEnd_;
            out_.validBytes = pos;
        }
        if (out_.complete) out_.validBytes = b_.size();
        out_.chunkCount = index_.chunks();
        return std::move(out_);
    }

private:
    void record(std::uint8_t op, std::uint64_t pos, Fields& f) {
        if (!sawHeader_ && op != mcap::kHeader) f.fail("the first record must be a Header");
        switch (op) {
            case mcap::kHeader:
                if (sawHeader_) f.fail("a second Header record");
                sawHeader_ = true;
                out_.profile = f.string("profile");
                out_.library = f.string("library");
                break;
            case mcap::kSchema:
                schema(f);
                break;
            case mcap::kChannel:
                channel(f);
                break;
            case mcap::kMessage:
                message(f);
                break;
            case mcap::kChunk:
                chunk(pos, f);
                break;
            case mcap::kMessageIndex:
                if (out_.hasDataEnd) f.fail("a MessageIndex record after DataEnd");
                index_.messageIndex(pos, f);
                break;
            case mcap::kChunkIndex:
                if (!out_.hasDataEnd) f.fail("a ChunkIndex record before DataEnd (it belongs to the summary)");
                index_.chunkIndex(f);
                break;
            case mcap::kDataEnd:
                dataEnd(pos, f);
                break;
            case mcap::kStatistics:
                statistics(f);
                break;
            case mcap::kSummaryOffset:
                if (firstSummaryOffset_ == 0) firstSummaryOffset_ = pos;
                break;
            case mcap::kFooter:
                footer(pos, f);
                break;
            default:
                break;  // index, attachment, metadata and application records: not needed here
        }
    }

    void schema(Fields& f) {
        McapSchema s;
        s.id = f.u16("id");
        s.name = f.string("name");
        s.encoding = f.string("encoding");
        const auto data = f.bytes(f.u32("data length"), "data");
        s.data.assign(data.begin(), data.end());
        if (s.id == 0) return;  // the spec calls schema id 0 invalid and says readers ignore it
        const auto known = schemaAt_.find(s.id);
        if (known == schemaAt_.end()) {
            schemaAt_[s.id] = out_.schemas.size();
            out_.schemas.push_back(std::move(s));
        } else if (!(out_.schemas[known->second] == s)) {
            f.fail("schema id " + std::to_string(s.id) + " redefined differently");
        }
    }

    void channel(Fields& f) {
        McapChannel c;
        c.id = f.u16("id");
        c.schemaId = f.u16("schema_id");
        c.topic = f.string("topic");
        c.messageEncoding = f.string("message_encoding");
        Fields m = f.map("metadata");
        while (!m.empty()) {
            std::string key = m.string("metadata key");
            if (!c.metadata.emplace(key, m.string("metadata value")).second) m.fail("duplicate key '" + key + "'");
        }
        if (c.schemaId != 0 && !schemaAt_.count(c.schemaId))
            f.fail("channel '" + c.topic + "' refers to schema id " + std::to_string(c.schemaId) +
                   ", which no earlier Schema record defines");
        const auto known = channelAt_.find(c.id);
        if (known == channelAt_.end()) {
            channelAt_[c.id] = out_.channels.size();
            out_.channels.push_back(std::move(c));
        } else if (!(out_.channels[known->second] == c)) {
            f.fail("channel id " + std::to_string(c.id) + " redefined differently");
        }
    }

    // A Chunk: its uncompressed records are Schema, Channel and Message records (nothing else).
    void chunk(std::uint64_t pos, Fields& f) {
        if (out_.hasDataEnd) f.fail("a Chunk record after DataEnd (the summary holds no messages)");
        const mcap::ChunkContent c = mcap::readChunk(f);
        index_.chunk(pos, recordEnd_ - pos, c);
        const std::span<const std::uint8_t> r(c.records);
        for (std::uint64_t at = 0; at < r.size();) {
            if (r.size() - at < mcap::kRecordPrefix || loadLe(&r[at + 1], 8) > r.size() - at - mcap::kRecordPrefix)
                f.fail("the record at offset " + std::to_string(at) + " of its uncompressed records is cut short");
            const std::uint8_t op = r[at];
            const std::uint64_t len = loadLe(&r[at + 1], 8);
            Fields inner(r.subspan(at + mcap::kRecordPrefix, len), where_, op, pos, "inside a Chunk");
            if (op == mcap::kSchema) {
                schema(inner);
            } else if (op == mcap::kChannel) {
                channel(inner);
            } else if (op == mcap::kMessage) {
                const McapMessage& m = message(inner);
                if (m.logTimeNs < c.startNs || m.logTimeNs > c.endNs)
                    inner.fail("log time " + std::to_string(m.logTimeNs) + " outside the chunk's [" +
                               std::to_string(c.startNs) + ", " + std::to_string(c.endNs) + "]");
                index_.message(at, m.channelId, m.logTimeNs);
            } else {
                inner.fail("only Schema, Channel and Message records may be inside a Chunk");
            }
            at += mcap::kRecordPrefix + len;
        }
    }

    const McapMessage& message(Fields& f) {
        if (out_.hasDataEnd) f.fail("a Message record after DataEnd (the summary holds no messages)");
        McapMessage m;
        m.channelId = f.u16("channel_id");
        m.sequence = f.u32("sequence");
        m.logTimeNs = f.u64("log_time");
        m.publishTimeNs = f.u64("publish_time");
        const auto data = f.rest();
        m.data.assign(data.begin(), data.end());
        if (!channelAt_.count(m.channelId))
            f.fail("message on channel id " + std::to_string(m.channelId) + ", which no earlier Channel defines");
        out_.messages.push_back(std::move(m));
        return out_.messages.back();
    }

    void dataEnd(std::uint64_t pos, Fields& f) {
        if (out_.hasDataEnd) f.fail("a second DataEnd record");
        out_.hasDataEnd = true;
        out_.dataSectionCrc = f.u32("data_section_crc");
        summaryStart_ = recordEnd_;
        if (out_.dataSectionCrc == 0) return;  // 0: the writer did not compute it
        // The CRC covers every byte from the start of the file (magic included) up to this record.
        const std::uint32_t crc = mcap::crc32Update(0, b_.data(), static_cast<std::size_t>(pos));
        if (crc != out_.dataSectionCrc)
            f.fail("data section CRC mismatch: stored " + std::to_string(out_.dataSectionCrc) + ", computed " +
                   std::to_string(crc) + " (the file is corrupted)");
    }

    void statistics(Fields& f) {
        if (out_.statistics) f.fail("a second Statistics record");
        McapStatistics s;
        s.messageCount = f.u64("message_count");
        s.schemaCount = f.u16("schema_count");
        s.channelCount = f.u32("channel_count");
        s.attachmentCount = f.u32("attachment_count");
        s.metadataCount = f.u32("metadata_count");
        s.chunkCount = f.u32("chunk_count");
        s.messageStartTimeNs = f.u64("message_start_time");
        s.messageEndTimeNs = f.u64("message_end_time");
        Fields m = f.map("channel_message_counts");
        while (!m.empty()) {
            const std::uint16_t id = m.u16("channel id");
            if (!s.channelMessageCounts.emplace(id, m.u64("message count")).second)
                m.fail("duplicate channel id " + std::to_string(id));
        }
        out_.statistics = std::move(s);
    }

    void footer(std::uint64_t pos, Fields& f) {
        const std::uint64_t summaryStart = f.u64("summary_start");
        const std::uint64_t summaryOffsetStart = f.u64("summary_offset_start");
        const std::uint32_t summaryCrc = f.u32("summary_crc");
        if (!f.empty()) f.fail("content longer than the 20 bytes a Footer has");
        const std::uint64_t end = pos + mcap::kRecordPrefix + mcap::kFooterContent;
        if (b_.size() - end < 8) {
            if (tolerant_) return;  // the closing magic is cut: the records are all there, the file is not
            f.fail("no closing magic after the Footer");
        }
        if (!isMagic(b_, end)) f.fail("the 8 bytes after the Footer are not the MCAP magic");
        if (b_.size() - end > 8) f.fail(std::to_string(b_.size() - end - 8) + " bytes after the closing magic");
        if (!out_.hasDataEnd) f.fail("no DataEnd record before the Footer");
        out_.indexedChunks = index_.indexed();
        if (out_.statistics && out_.statistics->chunkCount != index_.chunks())
            f.fail("Statistics counts " + std::to_string(out_.statistics->chunkCount) + " chunks, the file holds " +
                   std::to_string(index_.chunks()));
        if (out_.indexedChunks != 0 && out_.indexedChunks != index_.chunks())
            f.fail("the summary indexes " + std::to_string(out_.indexedChunks) + " of the file's " +
                   std::to_string(index_.chunks()) + " chunks");
        if (out_.statistics && out_.statistics->messageCount != out_.messages.size())
            f.fail("Statistics counts " + std::to_string(out_.statistics->messageCount) + " messages, the file holds " +
                   std::to_string(out_.messages.size()));
        if (summaryStart != 0 && summaryStart != summaryStart_)
            f.fail("summary_start " + std::to_string(summaryStart) + " is not the first record after DataEnd (" +
                   std::to_string(summaryStart_) + ")");
        if (summaryOffsetStart != 0 && summaryOffsetStart != firstSummaryOffset_)
            f.fail("summary_offset_start " + std::to_string(summaryOffsetStart) +
                   " is not the first SummaryOffset record (" + std::to_string(firstSummaryOffset_) + ")");
        if (summaryCrc != 0 && summaryStart != 0) {
            // From the summary start through the Footer's summary_offset_start field.
            const std::uint64_t crcEnd = pos + mcap::kRecordPrefix + 8 + 8;
            const std::uint32_t crc = mcap::crc32Update(0, b_.data() + summaryStart, crcEnd - summaryStart);
            if (crc != summaryCrc)
                f.fail("summary CRC mismatch: stored " + std::to_string(summaryCrc) + ", computed " +
                       std::to_string(crc) + " (the file is corrupted)");
        }
        out_.complete = true;
    }

    std::span<const std::uint8_t> b_;
    const std::string& where_;
    bool tolerant_;
    McapFile out_;
    bool sawHeader_ = false;
    std::uint64_t recordEnd_ = 0;                     // offset just past the record being parsed
    std::map<std::uint16_t, std::size_t> schemaAt_;   // id -> index in out_.schemas
    std::map<std::uint16_t, std::size_t> channelAt_;  // id -> index in out_.channels
    std::uint64_t summaryStart_ = 0;                  // offset just after DataEnd
    std::uint64_t firstSummaryOffset_ = 0;            // offset of the first SummaryOffset record, 0 if none
    mcap::ChunkIndexCheck index_;                     // chunks read, against which indexes are checked
};

}  // namespace

const McapSchema* McapFile::schema(std::uint16_t id) const {
    for (const auto& s : schemas)
        if (s.id == id) return &s;
    return nullptr;
}

const McapChannel* McapFile::channel(std::uint16_t id) const {
    for (const auto& c : channels)
        if (c.id == id) return &c;
    return nullptr;
}

McapFile parseMcap(std::span<const std::uint8_t> bytes, const std::string& where, McapReadMode mode) {
    return Parser(bytes, where, mode).run();
}

McapFile readMcap(const std::string& path, McapReadMode mode, std::uint64_t maxFileBytes) {
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (ec) throw Error(path, "cannot read: " + ec.message());
    if (size > maxFileBytes)
        throw Error(path, "file is " + std::to_string(size) + " bytes, more than the " + std::to_string(maxFileBytes) +
                              " this reader accepts");
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
        throw Error(path, std::string("cannot read: ") + (in.eof() ? "file shrank while reading" : "I/O error"));
    return parseMcap(bytes, path, mode);
}

}  // namespace bop::recording
