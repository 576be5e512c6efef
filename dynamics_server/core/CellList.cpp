#include "CellList.hpp"

#include "Model.hpp"
#include "Threads.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop::core {

void CellList::build(const Box& box, double minCell, const std::vector<Eigen::Vector3d>& pos,
                     const std::vector<std::uint64_t>* key) {
    lo_ = box.lo;
    boxSize_ = box.size();
    periodic_ = box.periodic;
    for (int a = 0; a < 3; ++a) {
        n_[a] = std::max(1, int(std::floor(boxSize_[a] / minCell)));
        if (periodic_[a] && n_[a] < 3)
            throw std::invalid_argument("periodic box side shorter than 3 cutoffs: enlarge the box");
        width_[a] = boxSize_[a] / n_[a];
    }
    axis_ = {0, 1, 2};
    std::stable_sort(axis_.begin(), axis_.end(), [&](int a, int b) { return n_[a] < n_[b]; });
    const int cells = n_[0] * n_[1] * n_[2];
    start_.assign(std::size_t(cells) + 1, 0);
    cellOfParticle_.resize(pos.size());
    forEachIndex(pos.size(), [&](std::size_t i) { cellOfParticle_[i] = cellOf(pos[i]); });
    for (std::size_t i = 0; i < pos.size(); ++i) ++start_[std::size_t(cellOfParticle_[i]) + 1];
    for (int c = 0; c < cells; ++c) start_[std::size_t(c) + 1] += start_[std::size_t(c)];
    order_.resize(pos.size());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < pos.size(); ++i) order_[fill[std::size_t(cellOfParticle_[i])]++] = std::uint32_t(i);
    if (!key) return;
    if (key->size() != pos.size()) throw std::invalid_argument("cell list: keys and positions differ in number");
    forEachIndex(std::size_t(cells), [&](std::size_t c) {  // a cell's few particles, by key (insertion sort)
        for (std::uint32_t k = start_[c] + 1; k < start_[c + 1]; ++k) {
            const std::uint32_t i = order_[k];
            std::uint32_t j = k;
            for (; j > start_[c] && (*key)[order_[j - 1]] > (*key)[i]; --j) order_[j] = order_[j - 1];
            order_[j] = i;
        }
    });
}

int CellList::cellOf(const Eigen::Vector3d& p) const {
    int ijk[3];
    for (int a = 0; a < 3; ++a) {
        double u = std::floor((p[a] - lo_[a]) / width_[a]);
        if (!std::isfinite(u)) u = 0;
        if (periodic_[a]) u -= n_[a] * std::floor(u / n_[a]);  // in double: far positions stay defined
        ijk[a] = int(std::clamp(u, 0.0, double(n_[a] - 1)));
    }
    return index(ijk[0], ijk[1], ijk[2]);
}

bool CellList::neighbour(const std::array<int, 3>& x, const int d[3], Neighbour& out) const {
    int y[3];
    out.shift.setZero();
    for (int a = 0; a < 3; ++a) {
        y[a] = x[a] + d[a];
        if (y[a] >= 0 && y[a] < n_[a]) continue;
        if (!periodic_[a] || std::abs(d[a]) >= n_[a]) return false;
        const int wraps = y[a] < 0 ? -1 : 1;
        out.shift[a] = wraps * boxSize_[a];
        y[a] -= wraps * n_[a];
    }
    out.cell = index(y[0], y[1], y[2]);
    return true;
}

int CellList::halfStencil(int c, std::array<Neighbour, 14>& out) const {
    // Itself, then the offsets that are "forward" in the cell index: along the slowest axis
    // (ds > 0), or ds == 0 and along the middle one (dm > 0), or ds == dm == 0 and the fastest (df > 0).
    const auto x = coords(c);
    int count = 0;
    out[count++] = {c, Eigen::Vector3d::Zero()};
    for (int ds = 0; ds <= 1; ++ds)
        for (int dm = -1; dm <= 1; ++dm)
            for (int df = -1; df <= 1; ++df) {
                const bool forward = ds > 0 || dm > 0 || (dm == 0 && df > 0);
                int d[3];
                d[axis_[0]] = df, d[axis_[1]] = dm, d[axis_[2]] = ds;
                if (forward && neighbour(x, d, out[std::size_t(count)])) ++count;
            }
    return count;
}

void CellList::forwardRanges(int c, int reach, std::vector<std::array<std::uint32_t, 2>>& out) const {
    if (periodic_[0] || periodic_[1] || periodic_[2])
        throw std::logic_error("cell list: forward ranges of a periodic list would need image shifts");
    out.clear();
    const auto x = coords(c);
    const int f = axis_[0], m = axis_[1], s = axis_[2];
    for (int ds = 0; ds <= reach && x[std::size_t(s)] + ds < n_[s]; ++ds)
        for (int dm = ds == 0 ? 0 : -reach; dm <= reach; ++dm) {
            const int ym = x[std::size_t(m)] + dm;
            if (ym < 0 || ym >= n_[m]) continue;
            // Along the fastest axis: from c itself in its own row, else `reach` cells either side.
            const int f0 = std::max(0, x[std::size_t(f)] - (ds == 0 && dm == 0 ? 0 : reach));
            const int f1 = std::min(n_[f] - 1, x[std::size_t(f)] + reach);
            int y[3];
            y[f] = f0, y[m] = ym, y[s] = x[std::size_t(s)] + ds;
            const int first = index(y[0], y[1], y[2]);  // the row's cells are consecutive indices
            out.push_back({start_[std::size_t(first)], start_[std::size_t(first + f1 - f0 + 1)]});
        }
}

std::vector<std::array<int, 2>> CellList::forwardOffsets(int reach) const {
    std::vector<std::array<int, 2>> out;
    const int stepM = n_[axis_[0]], stepS = n_[axis_[0]] * n_[axis_[1]];
    for (int ds = 0; ds <= reach; ++ds)
        for (int dm = ds == 0 ? 0 : -reach; dm <= reach; ++dm) {
            const int row = ds * stepS + dm * stepM;
            out.push_back({row + (ds == 0 && dm == 0 ? 0 : -reach), row + reach});
        }
    return out;
}

void CellList::around(int c, int reach, std::vector<Neighbour>& out) const {
    out.clear();
    const auto x = coords(c);
    Neighbour nb;
    for (int dz = -reach; dz <= reach; ++dz)
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
                const int d[3] = {dx, dy, dz};
                if (neighbour(x, d, nb)) out.push_back(nb);
            }
}

}  // namespace bop::core
