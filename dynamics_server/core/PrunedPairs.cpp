#include "PrunedPairs.hpp"

#include "Threads.hpp"

namespace bop::core {
namespace {

constexpr std::size_t kRowBlock = 1024;         // rows per block of the threaded pruning
constexpr std::size_t kThreadedEntries = 4096;  // fewer entries: one thread prunes

// The pairs of `from` closer than sqrt(range2) at `pos`, row by row in the list's order; rows
// in fixed blocks joined in block order, so the copy does not depend on the thread count.
// parts: one vector per block, kept between calls with their capacity.
void keep(const NeighbourList::Pairs& from, const std::vector<Eigen::Vector3d>& pos, double range2,
          NeighbourList::Pairs& to, std::vector<std::vector<std::uint32_t>>& parts) {
    to.start.assign(from.start.size(), 0);
    if (from.start.size() < 2) {
        to.nbr.clear();
        return;
    }
    const std::size_t rows = from.start.size() - 1;
    parts.resize(blockCount(rows, kRowBlock));
    forBlocks(
        rows, kRowBlock,
        [&](std::size_t b, std::size_t x0, std::size_t x1) {
            std::vector<std::uint32_t>& kept = parts[b];
            kept.clear();
            kept.reserve(from.start[x1] - from.start[x0]);
            for (std::size_t x = x0; x < x1; ++x) {
                const Eigen::Vector3d px = pos[x];
                const std::size_t before = kept.size();
                for (std::uint32_t k = from.start[x]; k < from.start[x + 1]; ++k)
                    if ((pos[from.nbr[k]] - px).squaredNorm() < range2) kept.push_back(from.nbr[k]);
                to.start[x + 1] = std::uint32_t(kept.size() - before);  // the row's length, summed below
            }
        },
        1, rows >= kThreadedEntries, true);
    for (std::size_t x = 1; x < to.start.size(); ++x) to.start[x] += to.start[x - 1];
    concatenate(parts, to.nbr);
}

}  // namespace

void PrunedPairs::prune(const NeighbourList& list, double ljRange, double wideRange, double maxMove) {
    const std::vector<Eigen::Vector3d>& pos = list.positions();
    keep(list.pairs(), pos, ljRange * ljRange, lj_, parts_);
    keep(list.haloPairs(), pos, ljRange * ljRange, ljHalo_, parts_);
    keep(list.widePairs(), pos, wideRange * wideRange, wide_, parts_);
    keep(list.wideHaloPairs(), pos, wideRange * wideRange, wideHalo_, parts_);
    at_ = pos;
    maxMove2_ = maxMove * maxMove;
    build_ = list.builds();
    ++prunes_;
}

bool PrunedPairs::holds(const NeighbourList& list) const {
    const std::vector<Eigen::Vector3d>& pos = list.positions();
    if (list.builds() != build_ || pos.size() != at_.size()) return false;
    const double beyond = sumIndex(pos.size(), [&](std::size_t e) {      // on the threads
        return (pos[e] - at_[e]).squaredNorm() < maxMove2_ ? 0.0 : 1.0;  // NaN too: pruned again
    });
    return beyond == 0;
}

}  // namespace bop::core
