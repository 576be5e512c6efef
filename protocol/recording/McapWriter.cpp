#include "recording/McapWriter.hpp"

#include "bop/common/Error.hpp"
#include "recording/McapBytes.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>

#include <fcntl.h>
#include <unistd.h>

namespace bop::recording {

namespace {

using namespace mcap;

// Records are handed to the OS once this many bytes are buffered (bounds data lost in a crash).
constexpr std::size_t kFlushBytes = std::size_t(1) << 20;

[[noreturn]] void throwErrno(const std::string& where, const std::string& what, int err) {
    throw Error(where, what + ": " + std::strerror(err));
}

}  // namespace

McapWriter::McapWriter(std::string path, std::string profile, McapWriterOptions options)
    : path_(std::move(path)), partialPath_(path_ + ".partial"), options_(options) {
    if (path_.empty()) throw Error("McapWriter", "empty output path");
    if (options_.compression == McapCompression::Zstd && (options_.zstdLevel < 1 || options_.zstdLevel > 19))
        throw Error(path_, "zstd level " + std::to_string(options_.zstdLevel) + " (expected 1 to 19)");
    fd_ = ::open(partialPath_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) throwErrno(partialPath_, "cannot create recording", errno);
    // The magic belongs to the data-section CRC: DataEnd's CRC covers the file from byte 0.
    buffer_.assign(mcap::kMagic.begin(), mcap::kMagic.end());
    dataCrc_ = mcap::crc32Update(0, buffer_.data(), buffer_.size());
    offset_ = buffer_.size();
    Bytes header;
    putString(header, profile, partialPath_, "profile");
    putString(header, "bop", partialPath_, "library");
    appendRecord(mcap::kHeader, header, true);
    flush();  // a reader of PATH.partial sees a valid start at once
}

McapWriter::~McapWriter() {
    if (fd_ < 0) return;  // closed, or failed earlier
    try {
        flush();  // keep what was recorded; PATH.partial stays unfinished (see header)
    } catch (...) {
        // Destructors must not throw; the partial file is still readable up to its last record.
    }
    if (fd_ >= 0) ::close(fd_);
}

void McapWriter::requireOpen(const char* what) const {
    if (closed_) throw Error(path_, std::string(what) + ": the recording is already closed");
    if (fd_ < 0) throw Error(partialPath_, std::string(what) + ": the recording failed earlier and is not writable");
}

std::uint16_t McapWriter::addSchema(const std::string& name, const std::string& encoding,
                                    std::span<const std::uint8_t> data) {
    requireOpen("addSchema");
    if (schemaRecords_.size() >= std::numeric_limits<std::uint16_t>::max())
        throw Error(partialPath_, "addSchema: too many schemas (MCAP schema ids are u16, 0 reserved)");
    const auto id = static_cast<std::uint16_t>(schemaRecords_.size() + 1);
    Bytes content;
    putU16(content, id);
    putString(content, name, partialPath_, "schema name");
    putString(content, encoding, partialPath_, "schema encoding");
    putU32(content, u32Length(data.size(), partialPath_, "schema data of '" + name + "'"));
    content.insert(content.end(), data.begin(), data.end());
    appendRecord(mcap::kSchema, content, true);
    schemaRecords_.push_back(makeRecord(mcap::kSchema, content));
    return id;
}

std::uint16_t McapWriter::addChannel(std::uint16_t schemaId, const std::string& topic,
                                     const std::string& messageEncoding,
                                     const std::map<std::string, std::string>& metadata) {
    requireOpen("addChannel");
    if (schemaId > schemaRecords_.size())
        throw Error(partialPath_, "addChannel '" + topic + "': unknown schema id " + std::to_string(schemaId) +
                                      " (expected 0 or an id returned by addSchema)");
    if (channelRecords_.size() >= std::numeric_limits<std::uint16_t>::max())
        throw Error(partialPath_, "addChannel: too many channels (MCAP channel ids are u16)");
    const auto id = static_cast<std::uint16_t>(channelRecords_.size() + 1);
    Bytes content;
    putU16(content, id);
    putU16(content, schemaId);
    putString(content, topic, partialPath_, "channel topic");
    putString(content, messageEncoding, partialPath_, "message encoding of '" + topic + "'");
    putStringMap(content, metadata, partialPath_);
    appendRecord(mcap::kChannel, content, true);
    channelRecords_.push_back(makeRecord(mcap::kChannel, content));
    channelMessageCounts_.push_back(0);
    return id;
}

void McapWriter::write(std::uint16_t channelId, std::uint32_t sequence, std::uint64_t logTimeNs,
                       std::uint64_t publishTimeNs, std::span<const std::uint8_t> data) {
    requireOpen("write");
    if (channelId == 0 || channelId > channelRecords_.size())
        throw Error(partialPath_, "write: unknown channel id " + std::to_string(channelId) +
                                      " (expected an id returned by addChannel)");
    // Message: channel_id u16, sequence u32, log_time u64, publish_time u64, then the data bytes
    // up to the end of the record (no length prefix: the record length implies it).
    Bytes content;
    content.reserve(mcap::kMessageFixed + data.size());
    putU16(content, channelId);
    putU32(content, sequence);
    putU64(content, logTimeNs);
    putU64(content, publishTimeNs);
    content.insert(content.end(), data.begin(), data.end());
    if (options_.chunkBytes == 0) {
        appendRecord(mcap::kMessage, content, true);
    } else {
        chunk_.add(channelId, logTimeNs, makeRecord(mcap::kMessage, content));
        if (chunk_.bytes() >= options_.chunkBytes) sealChunk();
    }
    messageStartNs_ = messageCount_ == 0 ? logTimeNs : std::min(messageStartNs_, logTimeNs);
    messageEndNs_ = messageCount_ == 0 ? logTimeNs : std::max(messageEndNs_, logTimeNs);
    ++messageCount_;
    ++channelMessageCounts_[channelId - 1];
}

void McapWriter::appendRecord(std::uint8_t op, const Bytes& content, bool inDataSection) {
    const std::size_t start = buffer_.size();
    putU8(buffer_, op);
    putU64(buffer_, content.size());
    append(buffer_, content);
    const std::size_t n = buffer_.size() - start;
    if (inDataSection) dataCrc_ = mcap::crc32Update(dataCrc_, buffer_.data() + start, n);
    offset_ += n;
    if (buffer_.size() >= kFlushBytes) flushBuffer();
}

void McapWriter::appendData(const Bytes& records) {
    dataCrc_ = mcap::crc32Update(dataCrc_, records.data(), records.size());
    append(buffer_, records);
    offset_ += records.size();
    if (buffer_.size() >= kFlushBytes) flushBuffer();
}

void McapWriter::sealChunk() {
    if (chunk_.empty()) return;
    SealedChunk sealed = chunk_.seal(offset_, options_.compression, options_.zstdLevel, partialPath_);
    appendData(sealed.dataRecords);
    chunkIndexRecords_.push_back(std::move(sealed.chunkIndex));
}

void McapWriter::writeOut(const std::uint8_t* p, std::size_t n) {
    while (n > 0) {
        const ::ssize_t k = ::write(fd_, p, n);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) {
            const int err = k < 0 ? errno : EIO;
            ::close(fd_);
            fd_ = -1;  // later calls fail in requireOpen; the file keeps what reached it
            throwErrno(partialPath_, "cannot write recording", err);
        }
        p += k;
        n -= static_cast<std::size_t>(k);
    }
}

void McapWriter::flush() {
    if (fd_ < 0) return;
    sealChunk();
    flushBuffer();
}

void McapWriter::flushBuffer() {
    if (fd_ < 0) return;
    writeOut(buffer_.data(), buffer_.size());
    buffer_.clear();
}

void McapWriter::close() {
    if (closed_) return;
    requireOpen("close");
    closed_ = true;  // also after a failure below: a second close() must not append a second summary
    sealChunk();
    // DataEnd ends the data section; its CRC covers every byte before this record.
    Bytes dataEnd;
    putU32(dataEnd, dataCrc_);
    appendRecord(mcap::kDataEnd, dataEnd, false);

    // Summary section, built in memory so its CRC can go into the Footer. Records are grouped by
    // opcode (the spec requires it); Channels come before Statistics (required for its per-channel map).
    Bytes stats;  // Statistics record content
    putU64(stats, messageCount_);
    putU16(stats, static_cast<std::uint16_t>(schemaRecords_.size()));
    putU32(stats, static_cast<std::uint32_t>(channelRecords_.size()));
    putU32(stats, 0);  // attachment_count
    putU32(stats, 0);  // metadata_count
    putU32(stats, chunkCount());
    putU64(stats, messageStartNs_);  // earliest / latest log time in ns, 0 when there are no messages
    putU64(stats, messageEndNs_);
    Bytes counts;  // Map<u16 channel id, u64 count>, channels that have messages (as the reference writer)
    for (std::size_t i = 0; i < channelMessageCounts_.size(); ++i) {
        if (channelMessageCounts_[i] == 0) continue;
        putU16(counts, static_cast<std::uint16_t>(i + 1));
        putU64(counts, channelMessageCounts_[i]);
    }
    putU32(stats, u32Length(counts.size(), partialPath_, "channel message counts"));
    append(stats, counts);

    const std::uint64_t summaryStart = offset_;
    Bytes tail;
    Bytes offsets;  // SummaryOffset records: group opcode u8, group start u64, group length u64
    auto addGroup = [&](std::uint8_t op, const std::vector<Bytes>& records) {
        if (records.empty()) return;
        const std::uint64_t start = summaryStart + tail.size();
        for (const Bytes& r : records) append(tail, r);
        Bytes c;
        putU8(c, op);
        putU64(c, start);
        putU64(c, summaryStart + tail.size() - start);
        append(offsets, makeRecord(mcap::kSummaryOffset, c));
    };
    addGroup(mcap::kSchema, schemaRecords_);
    addGroup(mcap::kChannel, channelRecords_);
    addGroup(mcap::kStatistics, {makeRecord(mcap::kStatistics, stats)});
    addGroup(mcap::kChunkIndex, chunkIndexRecords_);
    const std::uint64_t summaryOffsetStart = summaryStart + tail.size();
    append(tail, offsets);

    // Footer: summary_crc covers the summary start through the Footer's summary_offset_start field.
    putU8(tail, mcap::kFooter);
    putU64(tail, mcap::kFooterContent);
    putU64(tail, summaryStart);
    putU64(tail, summaryOffsetStart);
    putU32(tail, mcap::crc32Update(0, tail.data(), tail.size()));
    tail.insert(tail.end(), mcap::kMagic.begin(), mcap::kMagic.end());
    append(buffer_, tail);
    offset_ += tail.size();
    flush();

    // Durable before visible: fsync the data, then rename, then fsync the folder (best effort:
    // some file systems refuse to open folders) so the rename itself survives a power loss.
    if (::fsync(fd_) != 0) throwErrno(partialPath_, "cannot flush recording to disk", errno);
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throwErrno(partialPath_, "cannot close recording", errno);
    if (std::rename(partialPath_.c_str(), path_.c_str()) != 0)
        throwErrno(path_, "cannot rename " + partialPath_ + " to the final name", errno);
    std::string dir = std::filesystem::path(path_).parent_path().string();
    if (dir.empty()) dir = ".";
    const int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dirFd >= 0) {
        ::fsync(dirFd);
        ::close(dirFd);
    }
}

}  // namespace bop::recording
