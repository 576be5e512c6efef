// The policy of a step's exchange (Exchange.hpp), in one place for one process and for ranks: for
// one process every piece is a no-op but the halo, which stays empty.
#include "Exchange.hpp"

namespace bop::core {

namespace {

Refreshed rebuild(Exchange& ex, Particles& p, Halo& halo, double range, bool balance) {
    const bool moved = balance && ex.rebalance(p);
    ex.buildHalo(p, range, halo);
    return moved ? Refreshed::Moved : Refreshed::Rebuilt;
}

}  // namespace

Refreshed Exchange::start(Particles& p, Halo& halo, double range) {
    return rebuild(*this, p, halo, range, true);
}

Refreshed Exchange::afterDrift(Particles& p, Halo& halo, double range, bool listHolds) {
    if (allTrue(listHolds)) {
        updateHalo(p, halo);
        return Refreshed::Kept;
    }
    migrate(p);
    return rebuild(*this, p, halo, range, imbalance(p.size()) > kRebalanceAbove);
}

Refreshed Exchange::afterChange(Particles& p, Halo& halo, double range) {
    if (!hasGhosts()) return Refreshed::Rebuilt;
    return rebuild(*this, p, halo, range, imbalance(p.size()) > kRebalanceAbove);
}

bool Exchange::widen(Particles& p, Halo& halo, double range) {
    if (wrapsEveryDrift()) return false;  // one process: its particles are in the box, it has no ghosts
    migrate(p);                           // (ranks wrap the periodic box as they migrate)
    if (hasGhosts()) buildHalo(p, range, halo);
    return true;
}

}  // namespace bop::core
