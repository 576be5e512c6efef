#pragma once
// The client side of a BoP session (docs/protocol.md): a DEALER socket to the server's control
// endpoint (Hello -> SceneInfo, commands and their replies, probes, feedback) and a SUB socket to
// its frame endpoint, subscribed to the rate tiers the client wants. Frames are reassembled by a
// FrameAssembler; either the caller pulls them (receiveFrame) or a receiver thread keeps the
// newest one in a slot (startReceiver / latestFrame), so that a render loop never waits on the
// network. Every inbound buffer goes through its decoder; a bad one is counted, never thrown.
//
// Threads: the control methods (connect, sendProbe, sendCommand, pollFeedback) are for one thread
// at a time; latestFrame() and stats() may be called from any thread.
#include "client/FrameAssembler.hpp"
#include "codec/DecodeResult.hpp"
#include "codec/Messages.hpp"

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace bop::protocol {

struct ClientOptions {
    Role role = Role::Viewer;
    float frameRateHz = 0;                  // wanted state-frame rate, wall Hz; 0 = every frame the server publishes
    bool readOnly = false;                  // asks for a session that may not send commands
    std::string clientName = "bop-client";  // for the server's logs, at most kMaxNameBytes
    // How long connect() waits for SceneInfo and sendCommand() for its reply when called without
    // a timeout, ms. A few seconds: a loaded server answers within a step or two.
    std::chrono::milliseconds receiveTimeout{5000};
    // CURVE (all z85, 40 characters; see CurveKeys.hpp). With a server key set, both sockets
    // encrypt and accept only a server holding the matching secret key; without a client pair, a
    // fresh one is made per session (the server does not authenticate clients).
    std::string curveServerKey;
    std::string curvePublicKey;
    std::string curveSecretKey;
    // Largest message ZeroMQ accepts on the SUB socket, bytes: one frame chunk (the server's
    // --chunk-bytes, 4 MiB by default) with room to spare; larger ones drop the connection.
    std::size_t maxFrameChunkBytes = std::size_t(64) << 20;
    // The same on the DEALER socket: a gradient-map piece (MapChunk, 1 MiB + 256 bytes) is the
    // largest control message.
    std::size_t maxControlBytes = kMaxMapChunkBytes;
    // Frame messages queued in the SUB socket before ZeroMQ drops newer ones, messages. Small, so
    // that a slow client sees recent frames rather than a backlog; a chunk is one message.
    int frameHighWaterMark = 16;
    AssemblerLimits assembler;
    // Frames as datagrams (the paper's UDP mode; transport/UdpStream.hpp): when set, Hello names
    // this local port and the server sends every frame of our tier there as one fragmented
    // message; the SUB socket then takes none. Only complete frames are taken; incomplete ones
    // count in ClientStats::udpFramesLost. 0: frames over the SUB socket.
    std::uint16_t udpFramePort = 0;
    // Probes as datagrams to the server's UDP probe port instead of over the DEALER socket; the
    // server answers a datagram prober with feedback datagrams. Needs a server with UDP on.
    bool probeOverUdp = false;
};

struct ClientStats {
    std::uint64_t framesReceived = 0;      // whole frames reassembled
    std::uint64_t framesLost = 0;          // frames begun but never completed (FrameAssembler)
    std::uint64_t staleChunks = 0;         // chunks of frames older than one already received
    std::uint64_t inconsistentFrames = 0;  // frames whose chunks disagreed
    std::uint64_t sequenceRestarts = 0;    // the server's frame numbering started again (a restart)
    std::uint64_t chunksReceived = 0;      // frame chunks taken from the SUB socket
    std::uint64_t malformed = 0;           // buffers refused by a decoder or of an unexpected kind
    std::uint64_t bytesReceived = 0;       // bytes of every frame message (topic and chunk)
    std::uint64_t repliesDropped = 0;      // command replies with no waiting request (late or foreign)
    std::uint64_t udpDatagrams = 0;        // frame datagrams read (ClientOptions::udpFramePort)
    std::uint64_t udpFramesLost = 0;       // frames whose datagrams did not all come (given up)
    std::uint64_t refusals = 0;            // Refusal messages from the server: messages of ours it refused
    std::string lastRefusal;               // the newest one: "<kind> <seq>: <reason>"
    std::uint64_t keepAlives = 0;          // Hellos sent again to keep the session (SceneInfo::sessionTimeoutS)
};

// The newest whole frame from the receiver thread: `count` grows by one per frame kept, so a
// renderer sees whether anything new arrived since its last look without copying the frame.
struct LatestFrame {
    std::shared_ptr<const StateFrame> frame;  // null before the first
    std::uint64_t count = 0;
};

class ClientSession {
public:
    explicit ClientSession(ClientOptions options = {});
    ~ClientSession();  // stops the receiver thread; closes the sockets without waiting (linger 0)
    ClientSession(const ClientSession&) = delete;
    ClientSession& operator=(const ClientSession&) = delete;

    // Connects to the control endpoint (tcp://HOST:PORT), says Hello, waits for SceneInfo, then
    // connects the SUB socket to the announced frame endpoint with our tiers. Calling it again
    // starts a new session (the receiver thread is stopped first). bop::Error naming the endpoint
    // when it cannot connect or no SceneInfo comes within `timeout` (no server there, or, with
    // CURVE, a server without the matching secret key: the handshake fails silently), or when the
    // server refuses our Hello (its reason).
    SceneInfo connect(const std::string& endpoint, std::chrono::milliseconds timeout);
    SceneInfo connect(const std::string& endpoint);  // waits options.receiveTimeout

    const SceneInfo& scene() const;  // the newest SceneInfo (a reattach may change it)
    bool connected() const;
    // Tier m of docs/protocol.md: frames n with 2^m dividing n reach us (0 = every frame).
    int frameTier() const;
    std::string frameEndpoint() const;  // where the SUB socket connected

    // Sends the probe on the DEALER socket without waiting; false when it was dropped (the
    // socket's send queue is full: the server is gone or not keeping up). EncodeError on an
    // invalid probe (k0 <= 0, a position not finite).
    bool sendProbe(const Probe& probe);
    // Sends the command and waits for the reply with its requestId; feedback and SceneInfo that
    // arrive meanwhile are kept. bop::Error when no reply comes within `timeout`, or when the
    // server refuses the command before it could read its request id (a Refusal, its reason).
    CommandReply sendCommand(const Command& command, std::chrono::milliseconds timeout);
    CommandReply sendCommand(const Command& command);
    // Sends the command without waiting for its reply (a 1 kHz loop's cuts); false when the send
    // queue is full. The reply, read later by pollFeedback(), counts in stats().repliesDropped.
    bool postCommand(const Command& command);
    // Downloads the server's gradient-map file (SceneInfo::mapBytes; the bytes of a .bopgm file,
    // common/include/bop/common/GradientMapFile.hpp) in pieces of 1 MiB, each waited for up to
    // `timeout`, calling `progress(bytes so far, total)` after each. bop::Error naming the
    // endpoint when the server has no map, the map is over `maxBytes`, or a piece does not come.
    std::vector<std::uint8_t> downloadMap(std::uint64_t maxBytes, std::chrono::milliseconds timeout,
                                          const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});
    // The map's edits since it was built (Feedback::mapEdits says how many the server has made):
    // asks for those from number `first` on without waiting, false when the send queue is full.
    // The answer (as many as fit in one message) is read by pollFeedback() and handed out once by
    // takeMapEdits(); a later answer replaces one not yet taken.
    bool requestMapEdits(std::uint32_t first);
    std::optional<MapEdits> takeMapEdits();
    // The newest feedback since the last call, reading what the DEALER socket holds; never waits.
    // It also keeps the session: when the server forgets silent sessions (SceneInfo::
    // sessionTimeoutS) and nothing went over the DEALER socket for a third of that, Hello goes
    // again (the answer, SceneInfo, replaces scene()). A client calls it at least that often.
    std::optional<Feedback> pollFeedback();
    // The same, waiting until feedback comes or `deadline` passes (to the microsecond, unlike a
    // ZeroMQ poll's milliseconds: a 1 kHz loop can wait for feedback up to its next tick).
    std::optional<Feedback> waitFeedback(std::chrono::steady_clock::time_point deadline);

    // Waits up to `timeout` for a whole frame, then takes everything already queued without
    // waiting more, and returns the newest whole frame (nothing if none completed in time).
    // std::logic_error while the receiver thread runs (it owns the SUB socket then).
    std::optional<StateFrame> receiveFrame(std::chrono::milliseconds timeout);
    // Gives a frame from receiveFrame() back, so that later frames are decoded into its memory
    // instead of fresh memory (large frames come several times faster). Ignored while the
    // receiver thread runs; that thread reuses the frames latestFrame() no longer hands out.
    void recycle(StateFrame&& frame);

    // The receiver thread: owns the SUB socket and keeps the newest whole frame for latestFrame().
    void startReceiver();
    void stopReceiver();  // joins it (within about one poll interval, 20 ms)
    bool receiving() const;
    LatestFrame latestFrame() const;
    // Why the receiver thread stopped on its own (a socket error), empty while it runs or after a
    // clean stop. It never throws out of the thread.
    std::string receiverError() const;

    ClientStats stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Tier m for a client wanting `wantedHz` of a server publishing at `publishHz` (both wall Hz):
// floor(log2(publish / wanted)) in 0..7, 0 when either rate is unknown (0) or wanted >= publish.
int frameTierFor(float publishHz, float wantedHz);

// The clients' --server-key and --client-key: the server's public key from its file (bop-keys'
// PREFIX.pub) and, when `clientPrefix` is given, this client's pair from PREFIX.pub and
// PREFIX.key (for a server that lets in listed clients only). Empty names leave CURVE off.
// bop::Error naming the file or option when a key cannot be read or a pair comes without a
// server key.
void useCurveKeys(ClientOptions& options, const std::string& serverKeyFile, const std::string& clientPrefix);

}  // namespace bop::protocol
