#pragma once
// Rank 0 of a served run turns clients' commands into run commands (parallel/Commands.hpp) or
// changes of its controls (pause, single steps, the probe, damping), and starts or stops recording.
// Each answer names the step at which the command takes effect, or why it was refused.
#include "codec/DecodeResult.hpp"
#include "codec/Messages.hpp"
#include "core/ForceField.hpp"
#include "core/Run.hpp"
#include "server/ServerFront.hpp"

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace bop::app {

// Rank 0's state between passes: what clients asked for and what the run is doing.
struct ClientControls {
    bool paused = false;
    long long singleSteps = 0;   // steps still to do while paused
    std::uint64_t probeSeq = 0;  // the newest client probe's
    protocol::LoopStats loop;    // the newest probe's device loop (haptic clients), shown in frames
    bool clientProbe = false;    // the probe was last set by a client (not the scene)...
    std::chrono::steady_clock::time_point lastClientProbe{};  // ...at this time
};

// One client command (not Record): run commands submitted, or the controls changed. Checked again
// against the scene's ranges (server/InboundRanges.hpp): replayed commands come from a file.
protocol::CommandReply apply(const protocol::Command& c, ClientControls& controls, core::Run& run,
                             const protocol::SceneInfo& scene);

// Record start/stop. A client names at most a plain file name ending in .mcap: the recording
// goes into the server's output folder `outDir`, never elsewhere, and never replaces a file.
// Refused while the operator records the whole session (`operatorRecording`, --record).
protocol::CommandReply record(const protocol::Command& c, const protocol::Record& r, protocol::ServerFront& front,
                              const std::string& outDir, const std::string& operatorRecording, long long step);

}  // namespace bop::app
