#pragma once
// Cell lists over the simulation box (paper §4.5): cells at least one cutoff wide, particles
// binned by a counting sort, and a half stencil of 13 neighbour cells plus the cell itself so
// that every pair within the cutoff is visited exactly once. Particles outside a non-periodic
// box are binned into the border cells, which keeps every close pair in adjacent cells.
// Cells are numbered with the axis of fewest cells varying fastest and the axis of most cells
// slowest (x, y, z on ties): a stencil then reaches the fewest entries ahead in cell order, which
// keeps the pair loops' per-chunk buffers short (PairChunks.hpp).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace bop::core {

struct Box;

class CellList {
public:
    // Cells of at least minCell (simulation length units) across box; periodic axes need at
    // least 3 cells, otherwise that axis uses one cell and pairs take the minimum image. Within a
    // cell, particles by index, or by `key` (one per particle; equal keys by index) where given.
    void build(const Box& box, double minCell, const std::vector<Eigen::Vector3d>& pos,
               const std::vector<std::uint64_t>* key = nullptr);

    int cellCount() const { return int(start_.size()) - 1; }
    const std::array<int, 3>& dims() const { return n_; }
    // Particle indices sorted by cell; cell c holds order()[start(c) .. start(c+1)).
    const std::vector<std::uint32_t>& order() const { return order_; }
    std::uint32_t start(int c) const { return start_[std::size_t(c)]; }
    int cellOf(const Eigen::Vector3d& p) const;
    std::array<int, 3> coords(int c) const {
        std::array<int, 3> x;
        x[std::size_t(axis_[0])] = c % n_[axis_[0]];
        x[std::size_t(axis_[1])] = (c / n_[axis_[0]]) % n_[axis_[1]];
        x[std::size_t(axis_[2])] = c / (n_[axis_[0]] * n_[axis_[1]]);
        return x;
    }
    int index(int i, int j, int k) const {
        const int x[3] = {i, j, k};
        return x[axis_[0]] + n_[axis_[0]] * (x[axis_[1]] + n_[axis_[1]] * x[axis_[2]]);
    }

    struct Neighbour {
        int cell;               // neighbour cell index
        Eigen::Vector3d shift;  // add to the neighbour's positions (periodic image), length units
    };
    // The half stencil of cell c: itself first (shift 0), then up to 13 distinct neighbours.
    int halfStencil(int c, std::array<Neighbour, 14>& out) const;
    // The cells "forward" of c within `reach` cells along every axis (the half stencil of that
    // reach) as ranges [first, last) of order(), one per row of cells along the fastest axis,
    // the first starting at c itself (pairing an entry of c with those after it, start past it).
    // Non-periodic lists only: the ranges carry no image shifts.
    void forwardRanges(int c, int reach, std::vector<std::array<std::uint32_t, 2>>& out) const;
    // The same rows for a cell at least `reach` cells from every face (interior()), as cell index
    // offsets from it, first and last cell of each row: such a cell's ranges are
    // [start(c + first), start(c + last + 1)), found without its coordinates.
    std::vector<std::array<int, 2>> forwardOffsets(int reach) const;
    bool interior(int c, int reach) const {
        const auto x = coords(c);
        for (int a = 0; a < 3; ++a)
            if (x[std::size_t(a)] < reach || x[std::size_t(a)] >= n_[a] - reach) return false;
        return true;
    }
    // Every cell within `reach` cells of c (for range queries), with periodic shifts.
    void around(int c, int reach, std::vector<Neighbour>& out) const;

private:
    // The cell at offset d from cell coordinates x, with its periodic image shift; false if the
    // offset leaves a non-periodic box (or wraps a periodic axis more than once).
    bool neighbour(const std::array<int, 3>& x, const int d[3], Neighbour& out) const;

    std::array<int, 3> n_{1, 1, 1};
    std::array<int, 3> axis_{0, 1, 2};  // the axes from fastest-varying in the cell index to slowest
    Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), width_ = Eigen::Vector3d::Ones(), boxSize_ = Eigen::Vector3d::Ones();
    std::array<bool, 3> periodic_{false, false, false};
    std::vector<std::uint32_t> start_, order_;
    std::vector<int> cellOfParticle_;
};

}  // namespace bop::core
