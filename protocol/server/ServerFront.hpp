#pragma once
// The network front of bop-server (rank 0): a thread that owns every socket (ZeroMQ ROUTER for
// handshakes, commands and probes; PUB for state frames; UDP for probes and datagram frames)
// and talks to the step loop only through small mutex-guarded slots, so that a step never
// waits on a client (docs/protocol.md). The step loop takes commands and the newest probe,
// offers frames (the newest replaces one not yet sent) and feedback, and answers commands.
#include "codec/Messages.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bop::protocol {

struct FrontOptions {
    std::string bindAddress = "127.0.0.1";                 // interface to bind; "*" for all
    int basePort = 7700;                                   // control P, frames P+1, UDP probes P+2; 0 = ephemeral ports
    float publishHz = 60;                                  // default state-frame rate, wall Hz
    float maxPublishHz = 240;                              // the most a client may ask for, wall Hz
    std::size_t chunkBytes = 4u << 20;                     // largest frame chunk, bytes
    FrameEncoding frameEncoding = FrameEncoding::Float32;  // Quantised16, Compact8: smaller frames (codec/Quantise.hpp)
    bool frameIds = false;                                 // frames carry particle ids (8 bytes per particle more)
    bool viewersMayCommand = true;                         // false: viewers are read-only, only control clients command
    std::string curveSecretKey;                            // z85 server secret key; empty = no CURVE
    std::vector<std::string> curveClientKeys;  // z85 public keys of the clients let in (ZapHandler.hpp); empty = any
    bool udp = true;                           // probes on UDP P+2 and frames to clients' UDP ports; off with CURVE
    std::string recordPath;                    // MCAP recording of the session (SessionRecorder.hpp); empty = none
    std::map<std::string, std::string> recordMeta;  // scene file, ranks, ...: stored in the recording
    std::string mapFile;  // the gradient-map file clients may download (MapRequest); empty = none
    // A session the front has heard nothing from for this long is forgotten (clients keep theirs
    // with a Hello every third of it; SceneInfo announces it), ms.
    std::chrono::milliseconds sessionTimeout{30000};
};

struct FrontStats {
    std::uint64_t malformed = 0;       // inbound buffers refused by a decoder or of an unexpected kind
    std::uint64_t oversized = 0;       // of those, refused for their size
    std::uint64_t outOfRange = 0;      // whole messages refused for a value outside its range (docs/protocol.md)
    std::uint64_t refusalsSent = 0;    // Refusal messages and Rejected replies sent for the above
    std::uint64_t internalErrors = 0;  // exceptions caught in the front's threads (the front went on)
    std::string lastInternalError;     // what the last one said
    std::uint64_t framesSent = 0;      // frames published (all chunks)
    std::uint64_t framesDropped = 0;   // frames replaced before the publisher could send them, or not encodable
    std::uint64_t bytesSent = 0;       // frame bytes handed to the PUB socket
    std::uint64_t commands = 0, probes = 0, hellos = 0;
    std::uint64_t peersRefused = 0;     // CURVE handshakes refused: the client's key is not on the list
    std::size_t clients = 0;            // sessions now: identities that said Hello and are not forgotten
    std::uint64_t sessionsOpened = 0;   // identities that said Hello, over the run
    std::uint64_t sessionsExpired = 0;  // sessions forgotten after FrontOptions::sessionTimeout of silence
    // The step loop's waits for the slots' locks (ServerFrontImpl.hpp), held by the front's
    // threads (the only way the step loop can wait on the front): how many, the longest and all
    // together, ms.
    std::uint64_t loopWaits = 0;
    double loopWaitLongestMs = 0, loopWaitTotalMs = 0;
    std::string recordError;   // why recording stopped early, if it did
    std::string publishError;  // why the last frame that could not be encoded was not sent
};

// A command as the step loop sees it; answer it with ServerFront::reply().
struct PendingCommand {
    std::string client;  // opaque peer identity
    Command command;
};

class ServerFront {
public:
    // Binds the sockets (bop::Error naming the endpoint if one cannot be bound) and starts the thread.
    ServerFront(FrontOptions options, SceneInfo scene);
    ~ServerFront();
    ServerFront(const ServerFront&) = delete;
    ServerFront& operator=(const ServerFront&) = delete;

    int controlPort() const;
    int framePort() const;
    int udpProbePort() const;  // 0 without UDP
    std::string controlEndpoint() const;

    // ---- the step loop's side: none of these waits on the network ----
    std::vector<PendingCommand> takeCommands();
    std::optional<Probe> takeProbe();                          // the newest probe since the last call
    bool frameDue(std::chrono::steady_clock::time_point now);  // a publish tick has come
    void offerFrame(StateFrame frame);                         // a whole frame; chunked, encoded and sent by the thread
    void offerEncodedFrame(std::vector<std::vector<std::uint8_t>> chunks);  // sent as they are (replay)
    bool framePending() const;  // an offered frame is not sent yet (a replay waits: every frame counts)
    // The last frame sent, for its memory: gather the next frame into its arrays. Empty if none.
    StateFrame takeSpareFrame();
    // Neither throws: a feedback that is not finite or a reply that cannot be encoded is dropped
    // and counted as an internal error (FrontStats), so that the step loop never meets the
    // front's trouble.
    void offerFeedback(const Feedback& feedback);
    void reply(const PendingCommand& command, const CommandReply& reply);  // also recorded
    void probeApplied(const Probe& probe, std::uint64_t step);             // recorded when recording
    // Recording on request (the Record command): starts recording into `path`, finishing one
    // already running first (bop::Error naming the file if it cannot be created); stops and
    // finishes it, returning its file (empty when none was recording; bop::Error if the file
    // cannot be finished).
    void startRecording(const std::string& path);
    std::string stopRecording();
    // Stops the thread and finishes the recording (bop::Error if the file cannot be finished).
    void finish();
    void setParticleCount(std::uint64_t n);  // for SceneInfo of later handshakes
    // Every edit of the gradient map so far, for MapEditsRequest (the list grows; Feedback's
    // mapEdits, set by the step loop, says how long it is).
    void setMapEdits(std::shared_ptr<const std::vector<MapEdit>> edits);
    // Hands the front one message as if peer `id` had sent it on the control socket: the same
    // checks, sessions, counts and answers (sent to `id`, dropped when no such peer is connected),
    // without a socket. For tests and the front fuzzer (tests/fuzz/FuzzFront.cpp).
    void inject(const std::string& id, const std::uint8_t* data, std::size_t size);
    bool waitForClient(std::chrono::milliseconds timeout);  // until some client said Hello
    bool anyHaptic() const;                                 // some client sent a probe in the last second
    FrontStats stats() const;
    float publishHz() const;

private:
    void loopError(const std::string& what);  // the step loop's rare errors, counted with the front's
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace bop::protocol
