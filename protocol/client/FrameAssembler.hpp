#pragma once
// Reassembles state frames from their chunks (docs/protocol.md, "Chunks"), with no sockets: the
// caller decodes each chunk (decodeStateFrame) and feeds it here. A frame is handed out only when
// every chunk arrived and the chunks agree with each other; the newest frame wins, so a chunk of a
// frame not newer than the last one handed out is dropped, and a frame still incomplete when a
// newer one completes is given up as lost. Memory is bounded: a few partial frames and a byte cap.
//
// Each chunk is copied into place in its frame as it arrives. A receiver streaming large frames
// gives frames it is done with back (recycle) and decodes into spare(): at a million particles,
// taking fresh memory for every frame costs more than decoding it.
#include "codec/Messages.hpp"

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace bop::protocol {

struct AssemblerLimits {
    // Partial frames kept at once. Chunks of one frame travel back to back on one TCP stream, so
    // more than two or three incomplete frames means the older ones are not coming any more.
    std::size_t maxPartialFrames = 3;
    // Particle bytes (positions and normals as float32, species, ids as uint64) of the partial
    // frames, counted for the whole frame at its first chunk, so that a peer announcing huge
    // frames it never finishes cannot exhaust memory.
    std::size_t maxPartialBytes = std::size_t(512) << 20;
    // Consecutive stale chunks after which the sender is taken to number its frames from the
    // start again (a restarted server) and the last delivered sequence is forgotten; 0 = never.
    // One publisher over TCP never sends an older frame after a newer one, so a run of them means
    // a restart rather than reordering; without this a viewer would wait for ever.
    std::size_t restartAfterStale = 16;
};

struct AssemblerStats {
    std::uint64_t delivered = 0;     // whole frames handed out
    std::uint64_t lost = 0;          // frames begun but given up: superseded by a newer whole one, or over the limits
    std::uint64_t stale = 0;         // chunks dropped as part of a frame not newer than the last delivered
    std::uint64_t inconsistent = 0;  // frames whose chunks disagree (header, overlap, gap, repeated index)
    std::uint64_t restarts = 0;      // times the numbering restarted (AssemblerLimits::restartAfterStale)
};

class FrameAssembler {
public:
    explicit FrameAssembler(AssemblerLimits limits = {});

    // Takes one decoded chunk. Returns the whole frame when this chunk completed it: chunkIndex 0,
    // chunkCount 1, firstIndex 0, the header of its first chunk to arrive (chunks repeat their
    // frame's header) and the particles of all chunks in frame order. Returns nothing while the frame is incomplete, or
    // when the chunk was dropped (stale, inconsistent, over the limits: see stats()).
    std::optional<StateFrame> add(StateFrame chunk);

    const AssemblerStats& stats() const { return stats_; }
    // frameSeq of the last frame handed out; nothing before the first.
    std::optional<std::uint64_t> lastDelivered() const { return lastDelivered_; }
    std::size_t partialFrames() const { return partial_.size(); }
    std::size_t partialBytes() const { return heldBytes_; }  // particle bytes held, as counted against the cap
    // Storage of a frame the caller no longer needs, kept (up to kMaxSpares) for later frames.
    void recycle(StateFrame&& frame);
    // A frame whose arrays have capacity (the largest kept), or an empty one: decode into it.
    StateFrame spare();
    static constexpr std::size_t kMaxSpares = 3;
    // Forgets partial frames and the last delivered sequence (a new session: sequences restart);
    // keeps the stats.
    void reset();

private:
    struct Partial {
        bool givenUp = false;                          // inconsistent or over the limits: later chunks are ignored
        std::size_t bytes = 0;                         // particle bytes of the whole frame, reserved at its first chunk
        std::uint64_t particles = 0;                   // particles arrived
        std::vector<bool> seen;                        // by chunk index
        std::map<std::uint32_t, std::uint32_t> spans;  // particles arrived: first index -> count
        StateFrame whole;                              // header of the first chunk, arrays of the whole frame
    };
    using Iter = std::map<std::uint64_t, Partial>::iterator;

    std::optional<StateFrame> addChunk(Iter it, StateFrame chunk);
    bool fits(const Partial& p, const StateFrame& chunk) const;
    std::optional<StateFrame> deliver(std::uint64_t seq, StateFrame frame);
    void giveUp(Partial& p);  // frees its frame, keeps the entry as a tombstone
    void erase(Iter it, bool countLost);
    bool makeRoom(std::uint64_t seq);  // evicts oldest partial frames; false if `seq` itself went

    AssemblerLimits limits_;
    AssemblerStats stats_;
    std::optional<std::uint64_t> lastDelivered_;
    std::map<std::uint64_t, Partial> partial_;  // by frameSeq, oldest first
    std::size_t heldBytes_ = 0;
    std::size_t staleRun_ = 0;  // consecutive stale chunks
    std::vector<StateFrame> spares_;
};

}  // namespace bop::protocol
