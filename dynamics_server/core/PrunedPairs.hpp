#pragma once
// Dynamic pruning of the neighbour list (GROMACS prunes its cluster lists likewise): between two
// builds the pair loops read copies of the list's four sets of pairs that keep only the pairs
// closer than their loop's cutoff + an inner skin when pruned, in the list's order. Until some
// entry has moved half the inner skin since, every pair a copy dropped is still beyond its
// cutoff, so the loops compute the same forces, to the bit, over fewer pairs; then the copies
// are pruned again from the list. The list keeps its wider skin, so it is built as rarely.
#include "NeighbourList.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bop::core {

class PrunedPairs {
public:
    // The four sets the pair loops read, in NeighbourList's sense.
    struct Sets {
        const NeighbourList::Pairs *lj, *ljHalo, *wide, *wideHalo;
    };
    // The list's own sets, unpruned.
    static Sets whole(const NeighbourList& list) {
        return {&list.pairs(), &list.haloPairs(), &list.widePairs(), &list.wideHaloPairs()};
    }

    // Copies of the list's pairs within ljRange (its LJ pairs) and wideRange (its wide pairs) at
    // the entries' positions now, length units; they hold while every entry stays within
    // maxMove of where it is now (at most half of the smaller range's excess over its cutoff).
    void prune(const NeighbourList& list, double ljRange, double wideRange, double maxMove);
    // Whether the copies still serve `list`: the same build, no entry moved maxMove or farther.
    bool holds(const NeighbourList& list) const;

    Sets sets() const { return {&lj_, &ljHalo_, &wide_, &wideHalo_}; }
    std::size_t prunes() const { return prunes_; }
    std::size_t pairCount() const { return lj_.size() + ljHalo_.size(); }  // LJ pairs kept, the last pruning
    std::size_t widePairCount() const { return wide_.size() + wideHalo_.size(); }

private:
    NeighbourList::Pairs lj_, ljHalo_, wide_, wideHalo_;
    std::vector<Eigen::Vector3d> at_;                // entry positions at the pruning
    std::vector<std::vector<std::uint32_t>> parts_;  // per block of rows: the pairs kept (scratch)
    double maxMove2_ = 0;
    std::size_t build_ = 0, prunes_ = 0;
};

}  // namespace bop::core
