#pragma once
// Writes session recordings as MCAP files (https://mcap.dev/spec, major version "0"):
//   magic, Header, Schema and Channel records as they are added; Message records collected into
//   chunks (McapWriterOptions: about 1 MiB each, zstd-compressed), each chunk followed by one
//   MessageIndex record per channel in it; then close() appends DataEnd (CRC-32 of every byte
//   before it, magic included), a summary section (all Schema records, all Channel records, one
//   Statistics record, one ChunkIndex record per chunk), one SummaryOffset record per summary
//   group, Footer (with the summary CRC) and the closing magic. Indexed readers seek through the
//   summary; stream readers read the data section front to back. With chunkBytes = 0 every
//   Message record is written unchunked, as it comes.
// Timestamps are uint64 nanoseconds since an epoch the caller chooses (MCAP leaves it to the user;
// for BoP sessions use the same clock for every channel of a file).
//
// Crash safety: bytes go to PATH.partial; close() flushes and fsyncs it, renames it to PATH and
// fsyncs the folder, so PATH only ever names a complete file (an existing PATH is replaced).
// Until then PATH.partial holds every record handed to the OS (by flush(), by a chunk or the 1 MiB
// buffer filling up, or by the destructor), possibly followed by one record cut short; messages
// of the chunk being filled are in no record until it is sealed (flush() seals it); read it with
// readMcap(PATH.partial, McapReadMode::Tolerant), which stops after the last complete record.
// Destroying a writer without close() (e.g. during exception unwinding) flushes what is buffered
// and leaves PATH.partial unfinished on purpose: an interrupted session never looks complete.
//
// Errors: bop::Error(PATH.partial or PATH, what), e.g. an unwritable folder or an unknown channel.
// Not thread-safe: one thread (the recorder) owns a writer.
#include "recording/McapChunk.hpp"

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace bop::recording {

struct McapWriterOptions {
    std::size_t chunkBytes = std::size_t(1) << 20;  // uncompressed bytes a chunk collects; 0: no chunks
    McapCompression compression = McapCompression::Zstd;
    int zstdLevel = 3;  // 1 (fastest) .. 19 (smallest); 3 is zstd's own default
};

class McapWriter {
public:
    // Creates (truncates) PATH.partial and writes the magic and Header record (profile as given,
    // library "bop"). profile "" means no well-known MCAP profile (ros1/ros2 do not apply to BoP).
    explicit McapWriter(std::string path, std::string profile = "", McapWriterOptions options = {});
    ~McapWriter();
    McapWriter(const McapWriter&) = delete;
    McapWriter& operator=(const McapWriter&) = delete;

    // Writes a Schema record and returns its id (1, 2, ...; 0 means "no schema" in MCAP).
    // For FlatBuffers: encoding "flatbuffer", name the fully qualified root table (e.g. "bop.Frame"),
    // data the binary reflection schema (.bfbs from `flatc -b --schema`).
    std::uint16_t addSchema(const std::string& name, const std::string& encoding, std::span<const std::uint8_t> data);

    // Writes a Channel record and returns its id (1, 2, ...). schemaId is 0 or an id from addSchema;
    // messageEncoding e.g. "flatbuffer".
    std::uint16_t addChannel(std::uint16_t schemaId, const std::string& topic, const std::string& messageEncoding,
                             const std::map<std::string, std::string>& metadata = {});

    // Writes one Message record. logTimeNs: when the recorder received it; publishTimeNs: when the
    // sender produced it (MCAP asks for logTimeNs again if unknown). Both in nanoseconds.
    void write(std::uint16_t channelId, std::uint32_t sequence, std::uint64_t logTimeNs, std::uint64_t publishTimeNs,
               std::span<const std::uint8_t> data);

    // Seals the chunk being filled and hands buffered records to the OS (no fsync), so
    // PATH.partial is readable up to here. Every call ends a chunk: call it seldom.
    void flush();

    // Finishes the file as described above. Called once: a later call does nothing, also after a
    // failure (then PATH.partial keeps what reached it and the error named the step that failed).
    void close();

    const std::string& path() const { return path_; }
    const std::string& partialPath() const { return partialPath_; }
    std::uint64_t messageCount() const { return messageCount_; }
    std::uint32_t chunkCount() const { return static_cast<std::uint32_t>(chunkIndexRecords_.size()); }

private:
    void appendRecord(std::uint8_t op, const std::vector<std::uint8_t>& content, bool inDataSection);
    void appendData(const std::vector<std::uint8_t>& records);  // whole records, data section
    void sealChunk();
    void flushBuffer();
    void writeOut(const std::uint8_t* p, std::size_t n);
    void requireOpen(const char* what) const;

    std::string path_;
    std::string partialPath_;
    McapWriterOptions options_;
    int fd_ = -1;
    bool closed_ = false;
    std::vector<std::uint8_t> buffer_;  // records not yet handed to the OS
    std::uint64_t offset_ = 0;          // bytes emitted so far (written + buffered) = next record's offset
    std::uint32_t dataCrc_ = 0;         // CRC-32 of every byte from the file start to offset_
    std::vector<std::vector<std::uint8_t>> schemaRecords_;      // whole records, repeated in the summary
    std::vector<std::vector<std::uint8_t>> channelRecords_;     // index = id - 1
    std::vector<std::uint64_t> channelMessageCounts_;           // index = channel id - 1
    McapChunk chunk_;                                           // messages not yet in a Chunk record
    std::vector<std::vector<std::uint8_t>> chunkIndexRecords_;  // one per chunk, for the summary
    std::uint64_t messageCount_ = 0;
    std::uint64_t messageStartNs_ = 0;  // earliest log time written (ns); valid when messageCount_ > 0
    std::uint64_t messageEndNs_ = 0;    // latest log time written (ns)
};

}  // namespace bop::recording
