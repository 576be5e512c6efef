#include "NeighbourList.hpp"

#include "CellList.hpp"
#include "Threads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace bop::core {

namespace {

constexpr std::size_t kCellBlock = 64;          // cells per block of the threaded build (kCellsPerRange 1)
constexpr std::size_t kThreadedEntries = 4096;  // fewer entries: one thread builds the list

// Row lengths in p.start[1..] become offsets, and the blocks' neighbours are laid end to end.
void join(const std::vector<std::vector<std::uint32_t>>& parts, NeighbourList::Pairs& p) {
    std::size_t total = 0;
    for (const auto& q : parts) total += q.size();
    if (total >= std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("neighbour list: more than 2^32 pairs in one process; use more ranks");
    for (std::size_t e = 1; e < p.start.size(); ++e) p.start[e] += p.start[e - 1];
    concatenate(parts, p.nbr);
}

void checkSize(const NeighbourList::Pairs& a, const NeighbourList::Pairs& b) {
    if (a.nbr.size() >= std::numeric_limits<std::uint32_t>::max() ||
        b.nbr.size() >= std::numeric_limits<std::uint32_t>::max())
        throw std::length_error("neighbour list: more than 2^32 pairs in one process; use more ranks");
}

}  // namespace

int NeighbourList::kind(std::uint32_t x, std::uint32_t y) const {
    // Newton pairs: particle-particle, and particle-image kept only between the smaller particle
    // index and the image of the other (the pair appears once each way); two images never pair.
    // Halo pairs: a particle (not an image of it: that would count the pair twice) with a halo
    // ghost or its image; two ghosts never pair.
    const std::size_t n = particles_;
    const bool ghostX = owner_[x] >= n, ghostY = owner_[y] >= n;
    if (ghostX && ghostY) return 0;
    if (ghostX || ghostY) return (ghostX ? image_[y] : image_[x]) ? 0 : 2;
    if (image_[x] && image_[y]) return 0;
    if (image_[x] != image_[y] && (image_[x] ? key_[owner_[y]] > key_[owner_[x]] : key_[owner_[x]] > key_[owner_[y]]))
        return 0;
    return 1;
}

void NeighbourList::build(const Box& box, double range, const std::vector<Eigen::Vector3d>& pos,
                          const std::vector<Eigen::Vector3d>& halo, const Wide* wide,
                          const std::vector<std::uint64_t>* keys, double tier) {
    if (wide && wide->member.size() != pos.size() + halo.size())
        throw std::invalid_argument("neighbour list: wide members given for " + std::to_string(wide->member.size()) +
                                    " entries, not the " + std::to_string(pos.size() + halo.size()) +
                                    " particles and ghosts");
    if (keys && keys->size() != pos.size() + halo.size())
        throw std::invalid_argument("neighbour list: keys given for " + std::to_string(keys->size()) +
                                    " entries, not the " + std::to_string(pos.size() + halo.size()) +
                                    " particles and ghosts");
    if (keys) {
        key_ = *keys;
    } else {
        key_.resize(pos.size() + halo.size());
        std::iota(key_.begin(), key_.end(), std::uint64_t(0));
    }
    range_ = range;
    wideRange_ = wide ? wide->range : 0.0;
    const double reach = std::max(range_, wideRange_);  // of the images and of the box's extension
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
                extended.lo[a] -= reach;
                extended.hi[a] += reach;
            }
            continue;
        }
        if (L[a] < 2.0 * reach)
            throw std::invalid_argument("periodic box side " + std::to_string(L[a]) +
                                        " is shorter than twice the neighbour range " + std::to_string(reach) +
                                        " (cutoff + skin): enlarge the box");
        for (auto& x : raw) x[a] -= L[a] * std::floor((x[a] - box.lo[a]) / L[a]);
        const std::size_t m = raw.size();
        for (std::size_t k = 0; k < m; ++k) {
            const double x = raw[k][a];
            const double shift = x < box.lo[a] + reach ? L[a] : x >= box.hi[a] - reach ? -L[a] : 0.0;
            if (shift == 0.0) continue;
            Eigen::Vector3d image = raw[k];
            image[a] += shift;
            raw.push_back(image);
            rawOwner.push_back(rawOwner[k]);
        }
        extended.lo[a] -= reach;
        extended.hi[a] += reach;
    }

    std::vector<std::uint64_t> rawKey(raw.size());
    forEachIndex(raw.size(), [&](std::size_t k) { rawKey[k] = key_[rawOwner[k]]; });
    CellList cells;
    cells.build(extended, range / kCellsPerRange, raw, &rawKey);  // an image never shares a cell with its owner
    const auto& order = cells.order();
    const std::size_t ne = raw.size();
    owner_.resize(ne);
    pos_.resize(ne);
    shift_.resize(ne);
    image_.resize(ne);
    forEachIndex(ne, [&](std::size_t k) {
        owner_[k] = rawOwner[order[k]];
        pos_[k] = raw[order[k]];
        shift_[k] = pos_[k] - now_[owner_[k]];
        image_[k] = order[k] >= originals;
    });

    // Rows on the threads, in fixed blocks of cells (rows of a block are contiguous entries),
    // each block's neighbours then joined in block order: the same list at any thread count.
    const double range2 = range * range, tier2 = tier * tier;
    const bool plain = ne == particles_;  // no images, no ghosts: every pair in range is a Newton pair
    pairs_.start.assign(ne + 1, 0);
    haloPairs_.start.assign(ne + 1, 0);
    const std::size_t cellCount = std::size_t(cells.cellCount());
    const std::size_t blocks = blockCount(cellCount, kCellBlock);
    rowParts_.resize(blocks);  // per block: the rows' neighbours; row lengths go to start
    haloRowParts_.resize(blocks);
    const std::vector<std::array<int, 2>> offsets = cells.forwardOffsets(kCellsPerRange);
    const auto rows = [&](std::size_t b, std::size_t c0, std::size_t c1) {
        std::vector<std::array<std::uint32_t, 2>> ahead;  // the cell's forward entries, in ranges
        std::vector<std::uint32_t>& nbr = rowParts_[b];
        std::vector<std::uint32_t>& hnbr = haloRowParts_[b];
        nbr.clear();
        hnbr.clear();
        std::vector<std::uint32_t> far, hfar;  // a row's neighbours at `tier` or beyond
        std::vector<std::uint32_t> cand;       // a row's candidates, those in range first
        std::vector<double> candD2;            // and their squared distances
        for (int c = int(c0); c < int(c1); ++c) {
            const std::uint32_t b0 = cells.start(c), b1 = cells.start(c + 1);
            if (b0 == b1) continue;
            if (cells.interior(c, kCellsPerRange)) {
                ahead.clear();
                for (const auto& [first, last] : offsets)
                    ahead.push_back({cells.start(c + first), cells.start(c + last + 1)});
            } else {
                cells.forwardRanges(c, kCellsPerRange, ahead);
            }
            if (plain) {  // every pair in range a Newton pair: candidates kept without branches
                std::size_t most = 0;
                for (const auto& r : ahead) most += r[1] - r[0];
                cand.resize(most);
                candD2.resize(most);
                for (std::uint32_t x = b0; x < b1; ++x) {
                    const Eigen::Vector3d px = pos_[x];
                    std::size_t n = 0;
                    for (std::size_t r = 0; r < ahead.size(); ++r)
                        for (std::uint32_t y = (r == 0 ? x + 1 : ahead[r][0]); y < ahead[r][1]; ++y) {
                            const double d2 = (pos_[y] - px).squaredNorm();
                            cand[n] = y;
                            candD2[n] = d2;
                            n += d2 < range2;
                        }
                    const std::size_t from = nbr.size();
                    nbr.resize(from + n + 1);  // one more: each pass writes before it decides
                    std::size_t w = from;      // those within tier first, then the others
                    for (std::size_t k = 0; k < n; ++k) nbr[w] = cand[k], w += candD2[k] < tier2;
                    for (std::size_t k = 0; k < n; ++k) nbr[w] = cand[k], w += !(candD2[k] < tier2);
                    nbr.pop_back();
                    pairs_.start[x + 1] = std::uint32_t(n);  // the row's length, for now
                }
                continue;
            }
            for (std::uint32_t x = b0; x < b1; ++x) {
                const std::size_t from = nbr.size(), hfrom = hnbr.size();
                const Eigen::Vector3d px = pos_[x];
                for (std::size_t r = 0; r < ahead.size(); ++r) {
                    for (std::uint32_t y = (r == 0 ? x + 1 : ahead[r][0]); y < ahead[r][1]; ++y) {
                        const double d2 = (pos_[y] - px).squaredNorm();
                        if (d2 >= range2) continue;
                        const int k = kind(x, y);
                        if (k == 1) (d2 < tier2 ? nbr : far).push_back(y);
                        if (k == 2) (d2 < tier2 ? hnbr : hfar).push_back(y);
                    }
                }
                nbr.insert(nbr.end(), far.begin(), far.end());
                hnbr.insert(hnbr.end(), hfar.begin(), hfar.end());
                far.clear();
                hfar.clear();
                pairs_.start[x + 1] = std::uint32_t(nbr.size() - from);  // the row's length, for now
                haloPairs_.start[x + 1] = std::uint32_t(hnbr.size() - hfrom);
            }
        }
    };
    forBlocks(cellCount, kCellBlock, rows, 1, ne >= kThreadedEntries);
    join(rowParts_, pairs_);
    join(haloRowParts_, haloPairs_);  // each join checks its size
    widePairs_ = {};
    wideHaloPairs_ = {};
    if (wide) buildWide(extended, *wide);
}

void NeighbourList::buildWide(const Box& extended, const Wide& wide) {
    // The members' entries in their own cells of the wide range; each pair found once through
    // the half stencil, then filed under its smaller entry index.
    const std::size_t ne = owner_.size();
    std::vector<std::uint32_t> members;
    std::vector<Eigen::Vector3d> at;
    for (std::uint32_t e = 0; e < ne; ++e)
        if (wide.member[owner_[e]]) members.push_back(e), at.push_back(pos_[e]);
    CellList cells;
    cells.build(extended, wide.range, at);
    const auto& order = cells.order();
    const double range2 = wide.range * wide.range;
    const bool grouped = !wide.together.empty();
    if (grouped && (wide.group.size() != wide.member.size() || wide.together.size() != wide.side * wide.side))
        throw std::invalid_argument("neighbour list: wide groups given for " + std::to_string(wide.group.size()) +
                                    " entries and a table of " + std::to_string(wide.together.size()) + " for side " +
                                    std::to_string(wide.side));
    using Found = std::vector<std::pair<std::uint32_t, std::uint32_t>>;  // (smaller, larger)
    // Per block of cells (on the threads), then joined in block order: Newton, halo.
    const std::size_t cellCount = std::size_t(cells.cellCount());
    std::vector<std::array<Found, 2>> part(blockCount(cellCount, kCellBlock));
    const auto rows = [&](std::size_t b, std::size_t c0, std::size_t c1) {
        std::array<CellList::Neighbour, 14> stencil;
        for (int c = int(c0); c < int(c1); ++c) {
            const std::uint32_t b0 = cells.start(c), b1 = cells.start(c + 1);
            if (b0 == b1) continue;
            const int m = cells.halfStencil(c, stencil);
            for (std::uint32_t u = b0; u < b1; ++u)
                for (int s = 0; s < m; ++s) {
                    const std::uint32_t e1 = cells.start(stencil[std::size_t(s)].cell + 1);
                    for (std::uint32_t v = (s == 0 ? u + 1 : cells.start(stencil[std::size_t(s)].cell)); v < e1; ++v) {
                        const std::uint32_t x = members[order[u]], y = members[order[v]];
                        if (grouped && !wide.together[wide.group[owner_[x]] * wide.side + wide.group[owner_[y]]])
                            continue;
                        if ((pos_[y] - pos_[x]).squaredNorm() >= range2) continue;
                        const int k = kind(x, y);
                        if (k > 0) part[b][std::size_t(k - 1)].emplace_back(std::min(x, y), std::max(x, y));
                    }
                }
        }
    };
    forBlocks(cellCount, kCellBlock, rows, 1, members.size() >= kThreadedEntries);
    Pairs* out[2] = {&widePairs_, &wideHaloPairs_};
    for (int k = 0; k < 2; ++k) {  // by the smaller entry, in the order found
        Pairs& p = *out[k];
        p.start.assign(ne + 1, 0);
        std::size_t total = 0;
        for (const auto& q : part) {
            total += q[std::size_t(k)].size();
            for (const auto& [x, _] : q[std::size_t(k)]) ++p.start[x + 1];
        }
        for (std::size_t e = 0; e < ne; ++e) p.start[e + 1] += p.start[e];
        p.nbr.resize(total);
        std::vector<std::uint32_t> fill(p.start.begin(), p.start.end() - 1);
        for (const auto& q : part)
            for (const auto& [x, y] : q[std::size_t(k)]) p.nbr[fill[x]++] = y;
    }
    checkSize(widePairs_, wideHaloPairs_);
}

bool NeighbourList::measure(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove) {
    if (pos.size() != particles_ || builds_ == 0) return false;
    // Minimum image of each displacement on periodic axes (infinite half-widths elsewhere).
    Eigen::Vector3d L = box.size(), half;
    for (int a = 0; a < 3; ++a) half[a] = box.periodic[std::size_t(a)] ? 0.5 * L[a] : HUGE_VAL;
    const double max2 = maxMove * maxMove;
    const double beyond = sumIndex(pos.size(), [&](std::size_t i) {  // on the threads: the particles moved too far
        Eigen::Vector3d d = pos[i] - built_[i];
        for (int a = 0; a < 3; ++a)
            if (std::abs(d[a]) > half[a]) d[a] -= L[a] * std::round(d[a] / L[a]);
        if (!(d.squaredNorm() <= max2)) return 1.0;
        now_[i] = built_[i] + d;
        return 0.0;
    });
    return beyond == 0;
}

void NeighbourList::move(const std::vector<Eigen::Vector3d>& halo) {
    if (halo.size() != halo_)
        throw std::invalid_argument("neighbour list: " + std::to_string(halo.size()) + " halo ghosts given, " +
                                    std::to_string(halo_) + " at the build");
    std::copy(halo.begin(), halo.end(), now_.begin() + std::ptrdiff_t(particles_));
    forEachIndex(owner_.size(), [&](std::size_t e) { pos_[e] = now_[owner_[e]] + shift_[e]; });
}

}  // namespace bop::core
