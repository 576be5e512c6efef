#include "ClusterPairs.hpp"

#include "core/Threads.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace bop::tools {

using core::blockCount;
using core::concatenate;
using core::forBlocks;
using core::forEachIndex;

namespace {
constexpr std::size_t kClusterBlock = 256;  // clusters per block of the threaded build
}

void ClusterPairs::build(const core::NeighbourList::Pairs& pairs, std::size_t entries,
                         const std::vector<char>& isVolume) {
    entries_ = entries;
    const std::size_t clusters = (entries + kSize - 1) / kSize;
    start.assign(clusters + 1, 0);
    volume.assign(clusters, 0);
    parts_.resize(blockCount(clusters, kClusterBlock));
    const bool any = pairs.start.size() == entries + 1;  // an empty set has no rows
    forBlocks(clusters, kClusterBlock, [&](std::size_t b, std::size_t c0, std::size_t c1) {
        std::vector<Entry>& out = parts_[b];
        out.clear();
        std::vector<Entry> row;
        for (std::size_t c = c0; c < c1; ++c) {
            row.clear();
            const std::size_t x1 = std::min(entries, kSize * (c + 1));
            for (std::size_t x = kSize * c; x < x1; ++x) volume[c] |= std::uint8_t((isVolume[x] != 0) << (x % kSize));
            for (std::size_t x = kSize * c; any && x < x1; ++x)
                for (std::uint32_t k = pairs.start[x]; k < pairs.start[x + 1]; ++k) {
                    const std::uint32_t y = pairs.nbr[k];
                    row.push_back({y / kSize, 1u << (kSize * (x % kSize) + y % kSize)});
                }
            std::sort(row.begin(), row.end(), [](const Entry& p, const Entry& q) { return p.j < q.j; });
            std::size_t kept = 0;
            for (const Entry& e : row) {  // one entry per cluster j, its lanes joined
                if (kept > 0 && out.back().j == e.j) {
                    out.back().lanes |= e.lanes;
                    continue;
                }
                out.push_back(e);
                ++kept;
            }
            start[c + 1] = std::uint32_t(kept);
        }
    });
    for (std::size_t c = 1; c <= clusters; ++c) {
        if (std::size_t(start[c - 1]) + start[c] >= std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("cluster pairs: more than 2^32 in one process; use more ranks");
        start[c] += start[c - 1];
    }
    concatenate(parts_, list);
    pos.assign(3 * kSize * clusters, 0.0);
}

void ClusterPairs::setPositions(const Eigen::Vector3d* e) {
    forEachIndex(clusterCount(), [&](std::size_t c) {
        double* p = pos.data() + 3 * kSize * c;
        for (std::size_t a = 0; a < kSize; ++a) {
            const std::size_t x = kSize * c + a;
            for (std::size_t k = 0; k < 3; ++k) p[kSize * k + a] = x < entries_ ? e[x][Eigen::Index(k)] : 0.0;
        }
    });
}

std::size_t ClusterPairs::laneCount() const {
    std::size_t n = 0;
    for (const Entry& e : list) n += std::size_t(__builtin_popcount(e.lanes));
    return n;
}

}  // namespace bop::tools
