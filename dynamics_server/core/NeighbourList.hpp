#pragma once
// Verlet neighbour list built from cell lists (paper §4.5 and its expected "double frame rate"):
// every pair closer than cutoff + skin is stored once (half list, Newton's third law), and the
// list is reused until some particle has moved more than skin / 2 since it was built.
//
// The list works on entries: the particles, sorted by cell for memory locality; on periodic
// axes of the box, their images within cutoff + skin of the opposite face; and optionally
// halo ghosts, particles owned elsewhere (another rank's subdomain) whose positions the caller
// supplies. A pair of a particle with an image of another is stored once (smaller particle
// index with the image of the other); forces on images are folded back into their owners.
// A pair of a particle with a halo ghost goes to a separate list: its force counts on the
// particle only (the ghost's owner computes the other side), its energy and virial by half.
//
// Entry positions are unwrapped from the moment of the build: a particle that crosses a
// periodic face keeps a continuous entry position, so every stored pair stays valid.
//
// A second, wider set of pairs may be built at the same time over a subset of the entries (the
// bag's oriented surface particles, whose terms reach 3 r0 while LJ reaches 1.6 r0): the same
// rules, its own range, stored by the smaller entry index.
#include "Model.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace bop::core {

class NeighbourList {
public:
    // The entries are binned in cells of at least range / kCellsPerRange, and each finds its
    // neighbours in the cells within kCellsPerRange of its own, read as one range of entries
    // per row of cells. Cells of half the range (2) visit about 40% fewer candidates (63 cells of
    // an eighth the volume instead of 14), and built the 10^6-particle torus's list as fast as
    // whole-range cells once a cell's rows came from fixed offsets; but the particles, sorted by
    // the same cells (SpatialOrder.hpp), then mix surface and volume more finely, and the
    // integrator, the map and the pair loops lost more than the list gained at 10^5 particles
    // (docs/dynamics.md).
    static constexpr int kCellsPerRange = 1;

    struct Pairs {  // neighbours of entry e: nbr[start[e] .. start[e + 1]), entry indices
        std::vector<std::uint32_t> start, nbr;
        std::size_t size() const { return nbr.size(); }
    };

    // The wide pairs: range (simulation length units, at least the list's range) and which
    // particles, then halo ghosts, take part (member[k] != 0).
    // With `together` (side x side, row a, column b) the pairs are only those of two members
    // whose groups a, b (group[k], per particle then ghost) it joins: a bag's surface with its
    // own, not with another bag's, whose oriented weights are zero.
    struct Wide {
        double range = 0;
        std::vector<char> member;
        std::vector<std::uint8_t> group;
        std::vector<char> together;
        std::size_t side = 0;
    };

    // range: cutoff + skin, simulation length units. Periodic axes need a side of at least
    // 2 * the larger range (std::invalid_argument otherwise). halo: positions of the halo
    // ghosts. wide: also build the wide pairs (widePairs(), wideHaloPairs()). keys: one per
    // particle, then per ghost (their ids): entries within a cell follow them, and a pair of a
    // particle with an image of another is kept on the side of the smaller key, so that the
    // list, and the sums over it, do not depend on the order of the particles. Without keys,
    // their indices serve. tier (length units): each row of pairs() and haloPairs() lists its
    // neighbours closer than this at the build first, then the others, each part in the order
    // of cells and keys; a pair loop whose cutoff is `tier` then sees its cutoff test change
    // outcome about once per row. The wide rows keep the order their pairs are found in.
    void build(const Box& box, double range, const std::vector<Eigen::Vector3d>& pos,
               const std::vector<Eigen::Vector3d>& halo = {}, const Wide* wide = nullptr,
               const std::vector<std::uint64_t>* keys = nullptr, double tier = 0);

    // Displacements since the build. Returns false when the particle count differs from the
    // build or a particle moved farther than maxMove (then build again).
    bool measure(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove);
    // Moves the entries by the last measured displacements; halo: the ghosts' positions now, in
    // the order of the build (std::invalid_argument if the count differs).
    void move(const std::vector<Eigen::Vector3d>& halo = {});
    // measure() then move(): the serial case.
    bool update(const Box& box, const std::vector<Eigen::Vector3d>& pos, double maxMove) {
        if (!measure(box, pos, maxMove)) return false;
        move();
        return true;
    }

    std::size_t particleCount() const { return particles_; }
    std::size_t entryCount() const { return owner_.size(); }
    std::size_t ghostCount() const { return owner_.size() - particles_; }  // images and halo
    std::size_t pairCount() const { return pairs_.size() + haloPairs_.size(); }
    std::size_t widePairCount() const { return widePairs_.size() + wideHaloPairs_.size(); }
    std::size_t builds() const { return builds_; }
    double range() const { return std::max(range_, wideRange_); }  // the larger range: a halo's depth

    // Owner of each entry: a particle index below particleCount(), else particleCount() + the
    // index of a halo ghost.
    const std::vector<std::uint32_t>& owner() const { return owner_; }
    const std::vector<Eigen::Vector3d>& positions() const { return pos_; }  // current entry positions
    const std::vector<char>& images() const { return image_; }     // per entry: an image across a periodic face
    const Pairs& pairs() const { return pairs_; }                  // Newton pairs: forces to both sides
    const Pairs& haloPairs() const { return haloPairs_; }          // particle with halo ghost: one side
    const Pairs& widePairs() const { return widePairs_; }          // as pairs(), wide members, wide range
    const Pairs& wideHaloPairs() const { return wideHaloPairs_; }  // as haloPairs(), the same

private:
    // 0: no pair; 1: a Newton pair; 2: a halo pair (entries x, y within range).
    int kind(std::uint32_t x, std::uint32_t y) const;
    void buildWide(const Box& extended, const Wide& wide);

    double range_ = 0, wideRange_ = 0;
    std::size_t particles_ = 0, halo_ = 0, builds_ = 0;
    std::vector<std::uint32_t> owner_;
    std::vector<char> image_;         // per entry: an image of a particle or ghost across a periodic face
    std::vector<std::uint64_t> key_;  // per particle, then ghost: the build's keys (or indices)
    Pairs pairs_, haloPairs_, widePairs_, wideHaloPairs_;
    std::vector<Eigen::Vector3d> pos_, shift_;  // entry positions now; entry minus owner at the build
    std::vector<Eigen::Vector3d> built_;        // particle positions at the build
    std::vector<Eigen::Vector3d> now_;          // particles (unwrapped since the build), then halo
    // Per block of cells, the rows' neighbours of the last build (scratch, kept for its capacity).
    std::vector<std::vector<std::uint32_t>> rowParts_, haloRowParts_;
};

}  // namespace bop::core
