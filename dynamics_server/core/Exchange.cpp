// The policy of a step's exchange (Exchange.hpp), in one place for one process and for ranks: for
// one process every piece is a no-op but the halo, which stays empty.
#include "Exchange.hpp"

#include "SpatialOrder.hpp"

namespace bop::core {

void Exchange::sortIfDue(Particles& p, bool now) {
    if (sortEvery_ <= 0 || !(now || driftsSinceSort_ >= sortEvery_)) return;
    reorder(p, spatialOrder(sortBox_, sortCell_, p.pos, p.id));
    driftsSinceSort_ = 0;
}

// New cut planes (when `balance`), then the sort (when due, or `sortNow`), then the halo's plan,
// which names particles by index.
RegionChange Exchange::rebuild(Particles& p, Halo& halo, double range, bool balance, bool sortNow) {
    const bool moved = balance && rebalance(p);
    sortIfDue(p, sortNow);
    buildHalo(p, range, halo);
    return moved ? RegionChange::Moved : RegionChange::Rebuilt;
}

RegionChange Exchange::start(Particles& p, Halo& halo, double range) {
    return rebuild(p, halo, range, true, true);
}

RegionChange Exchange::afterDrift(Particles& p, Halo& halo, double range, bool listHolds) {
    ++driftsSinceSort_;
    if (allTrue(listHolds)) {
        updateHalo(p, halo);
        return RegionChange::Kept;
    }
    migrate(p);
    return rebuild(p, halo, range, imbalance(p.size()) > kRebalanceAbove, false);
}

RegionChange Exchange::afterChange(Particles& p, Halo& halo, double range) {
    if (!hasGhosts()) return RegionChange::Rebuilt;
    return rebuild(p, halo, range, imbalance(p.size()) > kRebalanceAbove, false);
}

bool Exchange::widen(Particles& p, Halo& halo, double range) {
    if (wrapsEveryDrift()) return false;  // one process: its particles are in the box, it has no ghosts
    migrate(p);                           // (ranks wrap the periodic box as they migrate)
    if (hasGhosts()) buildHalo(p, range, halo);
    return true;
}

}  // namespace bop::core
