#pragma once
// The pair loops work through a chunk's rows in blocks of list entries, four at a time: a pass
// over the block computes the entries' forces in V4 lanes (SimdMath.hpp) into the block's
// arrays, then a plain pass adds them to the particles, entry by entry in list order. The
// blocks follow the rows [x0, x1) of the chunk alone, so the sums do not depend on the thread
// count.
#include "NeighbourList.hpp"
#include "SimdMath.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace bop::core {

constexpr std::uint32_t kPairBlock = 128;  // entries per block (a multiple of 4): its arrays stay in L1 cache

struct PairBlocks {
    PairBlocks(const NeighbourList::Pairs& pairs, std::size_t x0, std::size_t x1)
        : start_(pairs.start.data()), nbr_(pairs.nbr.data()), x_(x0), k_(start_[x0]), end_(start_[x1]) {}

    // The next block: its first entry k0 and its length n (0 at the end). For q < n, entry
    // k0 + q pairs row i[q] with the list's nbr[k0 + q]; lanes up to the next multiple of 4
    // pair the last row with itself, and the loops mask them out by lanes(). j(q) gives the
    // second particles of lanes q..q+3: a pointer into the list, or for the block's last four
    // lanes a padded copy.
    [[gnu::always_inline]] std::uint32_t next(std::uint32_t& k0) {
        k0 = k_;
        const std::uint32_t n = std::min(kPairBlock, end_ - k_), kEnd = k_ + n;
        if (n == 0) return 0;
        std::uint32_t q = 0;
        while (k_ < kEnd) {
            while (start_[x_ + 1] <= k_) ++x_;  // the row of entry k_ (rows may be empty)
            const std::uint32_t rowEnd = std::min(start_[x_ + 1], kEnd);
            for (; k_ < rowEnd; ++k_) i[q++] = std::uint32_t(x_);
        }
        const std::uint32_t last = i[n - 1], tail = n - (n - 1) % 4 - 1;  // the last group's first lane
        for (q = n; q % 4 != 0; ++q) i[q] = last;
        for (std::uint32_t l = 0; l < 4; ++l) tail_[l] = tail + l < n ? nbr_[k0 + tail + l] : last;
        tailAt_ = tail;
        j0_ = nbr_ + k0;
        return n;
    }
    // The j of lanes q..q+3.
    [[gnu::always_inline]] const std::uint32_t* j(std::uint32_t q) const { return q == tailAt_ ? tail_ : j0_ + q; }

    std::uint32_t i[kPairBlock];

private:
    const std::uint32_t* start_;
    const std::uint32_t* nbr_;
    const std::uint32_t* j0_ = nullptr;
    std::size_t x_;
    std::uint32_t k_, end_;
    std::uint32_t tail_[4] = {}, tailAt_ = 0;
};

// Adds a block's results into the particles, entry by entry in list order: each entry's force
// and torque on j at once, those on i summed over its row and added when the row ends. A row that
// spans two blocks is summed as one, so the sums do not depend on where the blocks start. B: a
// block with fj, fi, ti, tj[3][kPairBlock] of doubles or floats; f, t: 3 doubles a particle,
// from the chunk's first row.
struct RowSums {
    double* f;
    double* t;
    std::size_t row = ~std::size_t(0);
    double fi[3] = {0, 0, 0}, ti[3] = {0, 0, 0};

    template <class B>
    [[gnu::always_inline]] void add(const B& b, const std::uint32_t* i, const std::uint32_t* nb, std::uint32_t n) {
        for (std::uint32_t q = 0; q < n; ++q) {
            if (i[q] != row) {
                finish();
                row = i[q];
            }
            const std::size_t j = 3 * std::size_t(nb[q]);
            for (int c = 0; c < 3; ++c) {
                f[j + c] += double(b.fj[c][q]);
                t[j + c] += double(b.tj[c][q]);
                fi[c] += double(b.fi[c][q]);
                ti[c] += double(b.ti[c][q]);
            }
        }
    }
    // Adds the open row's sums (at a row's end, and once after the last block).
    [[gnu::always_inline]] void finish() {
        if (row != ~std::size_t(0))
            for (int c = 0; c < 3; ++c) {
                f[3 * row + c] += fi[c], t[3 * row + c] += ti[c];
                fi[c] = ti[c] = 0;
            }
    }
};

// Lanes q..q+3 that hold entries of a block of n.
[[gnu::always_inline]] inline V4Mask lanes(std::uint32_t q, std::uint32_t n) {
    return (V4Mask{0, 1, 2, 3} + std::int64_t(q)) < std::int64_t(n);
}
// Component c of the 3-vectors a[idx[0..3]] (a: x, y, z packed).
[[gnu::always_inline]] inline V4 gather3(const double* a, const std::uint32_t* idx, int c) {
    return V4{a[3 * std::size_t(idx[0]) + c], a[3 * std::size_t(idx[1]) + c], a[3 * std::size_t(idx[2]) + c],
              a[3 * std::size_t(idx[3]) + c]};
}
[[gnu::always_inline]] inline void store4(double* to, V4 v) {
    std::memcpy(to, &v, sizeof v);
}
// The lanes' sum, lane 0 first: the same order every time.
[[gnu::always_inline]] inline double laneSum(V4 v) {
    return ((v[0] + v[1]) + v[2]) + v[3];
}

}  // namespace bop::core
