#pragma once
// A recorded session (recording/SessionRecorder.hpp) read back: the scene, the commands with the
// steps they were applied at, the probes with theirs, and the frame chunks as they were sent.
// Every message passes its decoder; a recording is untrusted input like the network.
#include "codec/Codec.hpp"

#include <map>
#include <string>
#include <vector>

namespace bop::protocol {

struct RecordedCommand {
    Command command;
    CommandReply reply;  // reply.step: the step at which it was applied
};
struct RecordedProbe {
    Probe probe;
    std::uint64_t step = 0;  // applied at the start of this step
};
struct RecordedChunk {
    std::uint64_t logTimeNs = 0;  // wall clock when it was sent, ns since the Unix epoch
    Buffer bytes;                 // the StateFrame chunk as sent
    StateFrame frame;             // decoded
};

struct RecordedSession {
    SceneInfo scene;
    std::map<std::string, std::string> meta;  // scene file, ranks, restart (the scene channel's metadata)
    std::vector<RecordedCommand> commands;    // in the order they were applied
    std::vector<RecordedProbe> probes;
    std::vector<RecordedChunk> chunks;  // in the order they were sent
};

// Reads PATH (a complete recording; PATH.partial files of an interrupted session are read up to
// their last complete record). bop::Error naming the file and what is wrong.
RecordedSession readSession(const std::string& path);

}  // namespace bop::protocol
