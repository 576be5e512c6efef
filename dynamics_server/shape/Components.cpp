#include "Components.hpp"

#include <algorithm>
#include <numeric>

namespace bop::shape {

Components findComponents(const Dims& dims, const std::function<bool(std::size_t)>& in) {
    Components c;
    c.label.assign(dims.count(), 0);
    std::vector<std::size_t> queue;
    std::uint32_t pieces = 0;
    for (std::size_t start = 0; start < dims.count(); ++start) {
        if (c.label[start] || !in(start)) continue;
        c.label[start] = ++pieces;
        queue.assign(1, start);
        for (std::size_t head = 0; head < queue.size(); ++head) {
            const std::size_t v = queue[head];
            const Eigen::Vector3i at = dims.coords(v);
            const int n[3] = {dims.nx, dims.ny, dims.nz};
            const std::size_t stride[3] = {1, std::size_t(dims.nx), std::size_t(dims.nx) * std::size_t(dims.ny)};
            for (int a = 0; a < 3; ++a)
                for (const int step : {-1, 1}) {
                    if (at[a] + step < 0 || at[a] + step >= n[a]) continue;
                    const std::size_t u = step < 0 ? v - stride[a] : v + stride[a];
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
