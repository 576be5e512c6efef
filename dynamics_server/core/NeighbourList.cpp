#include "NeighbourList.hpp"

#include "CellList.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace bop::core {

void NeighbourList::build(const Box& box, double range, const std::vector<Eigen::Vector3d>& pos) {
    range_ = range;
    particles_ = pos.size();
    ++builds_;
    built_ = pos;
    const Eigen::Vector3d L = box.size();

    // Raw entries: the particles (wrapped into the box on periodic axes), then ghost images,
    // axis by axis so that edge and corner images are images of images.
    std::vector<Eigen::Vector3d> raw(pos);
    std::vector<std::uint32_t> rawOwner(pos.size());
    std::iota(rawOwner.begin(), rawOwner.end(), 0u);
    Box extended = box;
    extended.periodic = {false, false, false};
    for (int a = 0; a < 3; ++a) {
        if (!box.periodic[std::size_t(a)]) continue;
        if (L[a] < 2.0 * range)
            throw std::invalid_argument("periodic box side " + std::to_string(L[a]) +
                                        " is shorter than twice the neighbour range " + std::to_string(range) +
                                        " (cutoff + skin): enlarge the box");
        for (auto& x : raw) x[a] -= L[a] * std::floor((x[a] - box.lo[a]) / L[a]);
        const std::size_t m = raw.size();
        for (std::size_t k = 0; k < m; ++k) {
            const double x = raw[k][a];
            const double shift = x < box.lo[a] + range ? L[a] : x >= box.hi[a] - range ? -L[a] : 0.0;
            if (shift == 0.0) continue;
            Eigen::Vector3d image = raw[k];
            image[a] += shift;
            raw.push_back(image);
            rawOwner.push_back(rawOwner[k]);
        }
        extended.lo[a] -= range;
        extended.hi[a] += range;
    }

    CellList cells;
    cells.build(extended, range, raw);
    const auto& order = cells.order();
    const std::size_t ne = raw.size();
    owner_.resize(ne);
    ref_.resize(ne);
    for (std::size_t k = 0; k < ne; ++k) {
        owner_[k] = rawOwner[order[k]];
        ref_[k] = raw[order[k]];
    }
    pos_ = ref_;

    // Half list: every close pair once; a pair with a ghost is kept only between the particle
    // with the smaller index and the ghost of the other, and two ghosts never pair.
    const std::uint32_t n = std::uint32_t(pos.size());
    const double range2 = range * range;
    start_.assign(ne + 1, 0);
    nbr_.clear();
    std::array<CellList::Neighbour, 14> stencil;
    for (int c = 0; c < cells.cellCount(); ++c) {
        const std::uint32_t b0 = cells.start(c), b1 = cells.start(c + 1);
        if (b0 == b1) continue;
        const int m = cells.halfStencil(c, stencil);
        for (std::uint32_t x = b0; x < b1; ++x) {
            const bool ghostX = order[x] >= n;
            for (int s = 0; s < m; ++s) {
                const std::uint32_t e0 = cells.start(stencil[std::size_t(s)].cell);
                const std::uint32_t e1 = cells.start(stencil[std::size_t(s)].cell + 1);
                for (std::uint32_t y = (s == 0 ? x + 1 : e0); y < e1; ++y) {
                    const bool ghostY = order[y] >= n;
                    if (ghostX && ghostY) continue;
                    if (ghostX != ghostY && (ghostX ? owner_[y] > owner_[x] : owner_[x] > owner_[y])) continue;
                    if ((ref_[y] - ref_[x]).squaredNorm() < range2) nbr_.push_back(y);
                }
            }
            // Nearest first: the pair loop's cutoff test then changes outcome once per entry,
            // which the branch predictor follows.
            const auto begin = nbr_.begin() + start_[x];
            std::sort(begin, nbr_.end(), [&](std::uint32_t u, std::uint32_t v) {
                const double du = (ref_[u] - ref_[x]).squaredNorm(), dv = (ref_[v] - ref_[x]).squaredNorm();
                return du < dv || (du == dv && u < v);
            });
            start_[x + 1] = std::uint32_t(nbr_.size());
        }
    }
}

bool NeighbourList::update(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove) {
    if (pos.size() != particles_) return false;
    // Minimum image of each displacement on periodic axes (infinite half-widths elsewhere).
    Eigen::Vector3d L = box.size(), half;
    for (int a = 0; a < 3; ++a) half[a] = box.periodic[std::size_t(a)] ? 0.5 * L[a] : HUGE_VAL;
    const double max2 = maxMove * maxMove;
    move_.resize(pos.size());
    for (std::size_t i = 0; i < pos.size(); ++i) {
        Eigen::Vector3d d = pos[i] - built_[i];
        for (int a = 0; a < 3; ++a)
            if (std::abs(d[a]) > half[a]) d[a] -= L[a] * std::round(d[a] / L[a]);
        if (!(d.squaredNorm() <= max2)) return false;
        move_[i] = d;
    }
    for (std::size_t e = 0; e < owner_.size(); ++e) pos_[e] = ref_[e] + move_[owner_[e]];
    return true;
}

}  // namespace bop::core
