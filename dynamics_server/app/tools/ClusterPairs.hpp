#pragma once
// The cluster-pair layout in the form the dynamics core would run it (bop-cluster-proto measures
// it; docs/dynamics.md, "A cluster-pair layout, built and measured"): the neighbour list's Newton
// pairs read as pairs of clusters, the list's entries four at a time in its own order (cell by
// cell), and for each cluster i the clusters j >= i it has some listed pair with, each with the
// lanes 4a + b (entry 4i + a with entry 4j + b) that the list holds. A loop then computes all
// sixteen lanes of a cluster pair at once, with no gathers, and keeps the listed lanes within its
// cutoff: the same pairs as the list's rows, counted once each. Built from the pairs a loop reads
// (the list's, or a pruned copy); the positions copied per step.
#include "core/NeighbourList.hpp"

#include <cstdint>
#include <vector>

namespace bop::tools {

class ClusterPairs {
public:
    static constexpr std::uint32_t kSize = 4;  // entries per cluster; 4 x 4 pairs fill sixteen float lanes

    struct Entry {
        std::uint32_t j;      // the second cluster (j >= the row's cluster)
        std::uint32_t lanes;  // bit 4a + b: entries (4i + a, 4j + b) are a listed pair
    };

    // From `pairs` (a Newton set of `entries` entries: each pair's second entry after its row):
    // rows of clusters, each row's clusters j in increasing order. volume: per entry, nonzero for
    // a volume particle (the virial's volume part).
    void build(const core::NeighbourList::Pairs& pairs, std::size_t entries, const std::vector<char>& volume);
    // The entries' positions now (length units), cluster by cluster: x of its four entries, then
    // y, then z; entries past the last (the last cluster's padding) at the origin.
    void setPositions(const Eigen::Vector3d* e);

    std::size_t clusterCount() const { return start.empty() ? 0 : start.size() - 1; }
    std::size_t entryCount() const { return entries_; }
    std::size_t pairCount() const { return list.size(); }  // cluster pairs
    std::size_t laneCount() const;                         // listed entry pairs (the list's pairs)

    std::vector<std::uint32_t> start;  // row i: list[start[i] .. start[i + 1])
    std::vector<Entry> list;
    std::vector<double> pos;           // 12 per cluster (setPositions)
    std::vector<std::uint8_t> volume;  // per cluster, bit a: entry 4c + a is a volume particle

private:
    std::size_t entries_ = 0;
    std::vector<std::vector<Entry>> parts_;  // per block of clusters (scratch, kept for its capacity)
};

}  // namespace bop::tools
