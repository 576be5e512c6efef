#pragma once
// `bop-replay export`: a recording rewritten chunked, indexed and compressed, with the Foxglove
// channels (FoxgloveChannels.hpp) derived from its frames. Every other message is copied as it
// is, on its own channel, with its times and sequence numbers; copies of the derived channels in
// the input are dropped and written afresh. An unfinished PATH.partial input is read up to its
// last complete record.
#include "recording/McapWriter.hpp"

#include <cstdint>
#include <string>

namespace bop::protocol {

struct ExportReport {
    std::uint64_t inputBytes = 0, outputBytes = 0;
    std::uint64_t messagesCopied = 0;  // wire messages, as they were
    std::uint64_t framesDerived = 0;   // whole frames turned into Foxglove messages
    std::uint32_t chunks = 0;          // chunks written
    double seconds = 0;                // recorded time span (first to last log time), s
};

// Throws bop::Error naming the file: an input that is not a BoP recording, an unwritable output.
ExportReport exportRecording(const std::string& in, const std::string& out,
                             const recording::McapWriterOptions& options = {});

}  // namespace bop::protocol
