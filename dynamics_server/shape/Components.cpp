#include "Components.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>

namespace bop::shape {

Components findComponents(const Dims& dims, const std::function<bool(std::size_t)>& in, Neighbours neighbours) {
    Components c;
    c.label.assign(dims.count(), 0);
    std::vector<Eigen::Vector3i> steps;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int reach = std::abs(dx) + std::abs(dy) + std::abs(dz);
                if (reach == 1 || (reach > 1 && neighbours == Neighbours::All)) steps.emplace_back(dx, dy, dz);
            }
    std::vector<std::size_t> queue;
    std::uint32_t pieces = 0;
    for (std::size_t start = 0; start < dims.count(); ++start) {
        if (c.label[start] || !in(start)) continue;
        c.label[start] = ++pieces;
        queue.assign(1, start);
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const Eigen::Vector3i at = dims.coords(queue[head]);
            for (const Eigen::Vector3i& step : steps) {
                const Eigen::Vector3i n = at + step;
                if (n.x() < 0 || n.y() < 0 || n.z() < 0 || n.x() >= dims.nx || n.y() >= dims.ny || n.z() >= dims.nz)
                    continue;
                const std::size_t u = dims.index(n.x(), n.y(), n.z());
                if (c.label[u] || !in(u)) continue;
                c.label[u] = pieces;
                queue.push_back(u);
            }
        }
        c.sizes.push_back(queue.size());
    }
    // Renumber largest first (stable: equal sizes keep their order).
    std::vector<std::uint32_t> order(pieces);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return c.sizes[a] > c.sizes[b]; });
    std::vector<std::uint32_t> rank(pieces + 1, 0);
    std::vector<std::size_t> sorted(pieces);
    for (std::uint32_t r = 0; r < pieces; ++r) {
        rank[order[r] + 1] = r + 1;
        sorted[r] = c.sizes[order[r]];
    }
    for (auto& l : c.label) l = rank[l];
    c.sizes = std::move(sorted);
    return c;
}

}  // namespace bop::shape
