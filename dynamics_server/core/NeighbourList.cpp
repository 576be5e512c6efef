#include "NeighbourList.hpp"

#include "CellList.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace bop::core {

void NeighbourList::build(const Box& box, double range, const std::vector<Eigen::Vector3d>& pos,
                          const std::vector<Eigen::Vector3d>& halo) {
    range_ = range;
    particles_ = pos.size();
    halo_ = halo.size();
    ++builds_;
    built_ = pos;
    now_ = pos;
    now_.insert(now_.end(), halo.begin(), halo.end());
    const Eigen::Vector3d L = box.size();

    // Raw entries: particles, halo ghosts (both wrapped into the box on periodic axes), then
    // images, axis by axis so that edge and corner images are images of images.
    std::vector<Eigen::Vector3d> raw(now_);
    std::vector<std::uint32_t> rawOwner(raw.size());
    std::iota(rawOwner.begin(), rawOwner.end(), 0u);
    const std::size_t originals = raw.size();
    Box extended = box;
    extended.periodic = {false, false, false};
    for (int a = 0; a < 3; ++a) {
        if (!box.periodic[std::size_t(a)]) {
            if (!halo.empty()) {  // room for the ghosts beyond the faces
                extended.lo[a] -= range;
                extended.hi[a] += range;
            }
            continue;
        }
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
    pos_.resize(ne);
    shift_.resize(ne);
    std::vector<char> image(ne);
    for (std::size_t k = 0; k < ne; ++k) {
        owner_[k] = rawOwner[order[k]];
        pos_[k] = raw[order[k]];
        shift_[k] = pos_[k] - now_[owner_[k]];
        image[k] = order[k] >= originals;
    }

    // Newton pairs: particle-particle, and particle-image kept only between the smaller particle
    // index and the image of the other (the pair appears once each way); two images never pair.
    // Halo pairs: a particle (not an image of it: that would count the pair twice) with a halo
    // ghost or its image; two ghosts never pair.
    const std::uint32_t n = std::uint32_t(pos.size());
    const double range2 = range * range;
    pairs_.start.assign(ne + 1, 0);
    haloPairs_.start.assign(ne + 1, 0);
    pairs_.nbr.clear();
    haloPairs_.nbr.clear();
    const auto nearestFirst = [&](std::vector<std::uint32_t>& list, std::uint32_t from, std::uint32_t x) {
        std::sort(list.begin() + from, list.end(), [&](std::uint32_t u, std::uint32_t v) {
            const double du = (pos_[u] - pos_[x]).squaredNorm(), dv = (pos_[v] - pos_[x]).squaredNorm();
            return du < dv || (du == dv && u < v);
        });
    };
    std::array<CellList::Neighbour, 14> stencil;
    for (int c = 0; c < cells.cellCount(); ++c) {
        const std::uint32_t b0 = cells.start(c), b1 = cells.start(c + 1);
        if (b0 == b1) continue;
        const int m = cells.halfStencil(c, stencil);
        for (std::uint32_t x = b0; x < b1; ++x) {
            const bool ghostX = owner_[x] >= n;
            for (int s = 0; s < m; ++s) {
                const std::uint32_t e0 = cells.start(stencil[std::size_t(s)].cell);
                const std::uint32_t e1 = cells.start(stencil[std::size_t(s)].cell + 1);
                for (std::uint32_t y = (s == 0 ? x + 1 : e0); y < e1; ++y) {
                    const bool ghostY = owner_[y] >= n;
                    if (ghostX && ghostY) continue;
                    if ((pos_[y] - pos_[x]).squaredNorm() >= range2) continue;
                    if (ghostX || ghostY) {  // the particle itself, never its image, with the ghost or its image
                        if (!(ghostX ? image[y] : image[x])) haloPairs_.nbr.push_back(y);
                        continue;
                    }
                    if (image[x] && image[y]) continue;
                    if (image[x] != image[y] && (image[x] ? owner_[y] > owner_[x] : owner_[x] > owner_[y])) continue;
                    pairs_.nbr.push_back(y);
                }
            }
            // Nearest first: the pair loop's cutoff test then changes outcome once per entry,
            // which the branch predictor follows.
            nearestFirst(pairs_.nbr, pairs_.start[x], x);
            nearestFirst(haloPairs_.nbr, haloPairs_.start[x], x);
            if (pairs_.nbr.size() >= std::numeric_limits<std::uint32_t>::max() ||
                haloPairs_.nbr.size() >= std::numeric_limits<std::uint32_t>::max())
                throw std::length_error("neighbour list: more than 2^32 pairs in one process; use more ranks");
            pairs_.start[x + 1] = std::uint32_t(pairs_.nbr.size());
            haloPairs_.start[x + 1] = std::uint32_t(haloPairs_.nbr.size());
        }
    }
}

bool NeighbourList::measure(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove) {
    if (pos.size() != particles_ || builds_ == 0) return false;
    // Minimum image of each displacement on periodic axes (infinite half-widths elsewhere).
    Eigen::Vector3d L = box.size(), half;
    for (int a = 0; a < 3; ++a) half[a] = box.periodic[std::size_t(a)] ? 0.5 * L[a] : HUGE_VAL;
    const double max2 = maxMove * maxMove;
    for (std::size_t i = 0; i < pos.size(); ++i) {
        Eigen::Vector3d d = pos[i] - built_[i];
        for (int a = 0; a < 3; ++a)
            if (std::abs(d[a]) > half[a]) d[a] -= L[a] * std::round(d[a] / L[a]);
        if (!(d.squaredNorm() <= max2)) return false;
        now_[i] = built_[i] + d;
    }
    return true;
}

void NeighbourList::move(const std::vector<Eigen::Vector3d>& halo) {
    if (halo.size() != halo_)
        throw std::invalid_argument("neighbour list: " + std::to_string(halo.size()) + " halo ghosts given, " +
                                    std::to_string(halo_) + " at the build");
    std::copy(halo.begin(), halo.end(), now_.begin() + std::ptrdiff_t(particles_));
    for (std::size_t e = 0; e < owner_.size(); ++e) pos_[e] = now_[owner_[e]] + shift_[e];
}

}  // namespace bop::core
