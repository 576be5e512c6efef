#pragma once
// The haptic client's map copy following the server's map (docs/haptics.md "Cutting"): feedback
// says how many edits the server has made (cuts from any client, yields of plasticity); while the
// copy has taken fewer, the follower asks for the rest (MapEditsRequest, one request at a time,
// never waiting) and hands each answer's edits to the cutter in the server's order. The client's
// own strokes reach the copy twice, once at once and once from the server: the second finds
// nothing left to take and leaves the map as it is.
#include "client/ClientSession.hpp"
#include "control/BladeCuts.hpp"

#include <cstdint>
#include <optional>

namespace bop::haptic {

class MapFollower {
public:
    explicit MapFollower(FieldCutter& cutter) : cutter_(cutter) {}

    // One loop tick at nowS (any steady clock, s): `serverEdits` from this tick's feedback (none
    // when none came). Reads the answer pollFeedback() kept; never waits.
    void tick(protocol::ClientSession& session, double nowS, std::optional<std::uint32_t> serverEdits);
    // A new session (the server restarted): its edits are taken from the first again.
    void restart();
    std::uint32_t taken() const { return taken_; }   // the server's edits handed to the cutter
    std::uint32_t known() const { return wanted_; }  // the most edits the server said it has
    std::uint64_t requests() const { return requests_; }

private:
    FieldCutter& cutter_;
    std::uint32_t taken_ = 0, wanted_ = 0;
    double nextAskS_ = -1e300;  // no request before then: one is out, or the server asked us to wait
    std::uint64_t requests_ = 0;
};

}  // namespace bop::haptic
