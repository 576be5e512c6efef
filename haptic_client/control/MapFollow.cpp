#include "control/MapFollow.hpp"

#include <algorithm>

namespace bop::haptic {
namespace {

constexpr double kAnswerWaitS = 1.0;  // a request unanswered this long is sent again
constexpr double kBusyWaitS = 0.05;   // after an answer with nothing in it (the server's budget)

}  // namespace

void MapFollower::tick(protocol::ClientSession& session, double nowS, std::optional<std::uint32_t> serverEdits) {
    if (serverEdits) wanted_ = std::max(wanted_, *serverEdits);
    if (std::optional<protocol::MapEdits> answer = session.takeMapEdits()) {
        wanted_ = std::max(wanted_, answer->total);
        const std::uint64_t end = std::uint64_t(answer->first) + answer->edits.size();
        if (answer->first <= taken_ && end > taken_) {
            for (std::size_t i = taken_ - answer->first; i < answer->edits.size(); ++i) {
                const protocol::MapEdit& e = answer->edits[i];
                cutter_.push(CopyEdit{{e.cut.from, e.cut.to, e.cut.radius}, e.voxels});
            }
            taken_ = std::uint32_t(end);
            nextAskS_ = nowS;
        } else {
            nextAskS_ = nowS + kBusyWaitS;
        }
    }
    if (taken_ >= wanted_ || nowS < nextAskS_) return;
    if (session.requestMapEdits(taken_)) {
        ++requests_;
        nextAskS_ = nowS + kAnswerWaitS;
    }
}

void MapFollower::restart() {
    taken_ = wanted_ = 0;
    nextAskS_ = -1e300;
}

}  // namespace bop::haptic
