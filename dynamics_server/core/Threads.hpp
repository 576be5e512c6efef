#pragma once
// Threads inside a process (OpenMP from the compiler): loops whose results do not depend on the
// number of threads. A per-particle loop writes only its particle's values; a sum runs over
// fixed blocks of kSumBlock items, each summed in order, and the block sums in order, so that the
// same bits come out at 1, 2 or 16 threads. Without OpenMP the loops run on the calling thread.
#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace bop::core {

inline constexpr std::size_t kSumBlock = 256;   // items per block of a sum
inline constexpr std::size_t kThreadMin = 256;  // loops shorter than this stay on one thread
// Per-particle and per-entry loops give each thread one contiguous range, the same in every loop
// of a step, as ranks own their subdomains: the particles are kept in the neighbour list's cell
// order (SpatialOrder.hpp), so a thread's range is a slab of the bag, its surface and volume
// particles mixed, and each core works on the same memory from phase to phase. Dealing turns of
// 64 particles instead made both cores pull every cache line (two threads 1.28x one at 10^5
// particles, against 1.93x for two ranks; docs/parallel.md).

inline int threadCount() {
#if defined(_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}
// The threads each later loop uses (at least 1; without OpenMP always 1).
inline void setThreadCount(int n) {
#if defined(_OPENMP)
    omp_set_num_threads(n > 0 ? n : 1);
#else
    (void)n;
#endif
}

// f(i) for i in [0, n), on the threads (a contiguous range each).
template <class F>
void forEachIndex(std::size_t n, F&& f) {
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n >= kThreadMin)
#endif
    for (std::size_t i = 0; i < n; ++i) f(i);
}

// The number of blocks of `block` items that cover [0, n).
inline std::size_t blockCount(std::size_t n, std::size_t block) {
    return (n + block - 1) / block;
}

// f(b, begin, end) for each block b = [b * block, min(n, (b + 1) * block)) of [0, n), on the
// threads when `threaded` and there are several: dynamic schedule, `grain` blocks at a time
// (blocks of uneven work, such as cells of which many are empty), or with `contiguous` a range
// of blocks each (blocks of even work over the particles' order, as the per-particle loops).
// The blocks depend on n and block alone: a caller that keeps each block's results and joins
// them in block order gets the same bits at any thread count.
template <class F>
void forBlocks(std::size_t n, std::size_t block, F&& f, std::size_t grain = 1, bool threaded = true,
               bool contiguous = false) {
    const std::size_t blocks = blockCount(n, block);
    if (contiguous) {
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (threaded && blocks > 1)
#endif
        for (std::size_t b = 0; b < blocks; ++b) f(b, b * block, std::min(n, (b + 1) * block));
        return;
    }
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, grain) if (threaded && blocks > 1)
#endif
    for (std::size_t b = 0; b < blocks; ++b) f(b, b * block, std::min(n, (b + 1) * block));
}

// The vectors of `parts` laid end to end in `out` (sized to their total; its earlier contents
// are overwritten, its capacity kept), each part copied on the threads.
template <class T>
void concatenate(const std::vector<std::vector<T>>& parts, std::vector<T>& out) {
    std::vector<std::size_t> at(parts.size() + 1, 0);
    for (std::size_t b = 0; b < parts.size(); ++b) at[b + 1] = at[b] + parts[b].size();
    if (at.back() > out.capacity()) {  // a new buffer with room to grow, the old one freed first, not copied
        out = std::vector<T>();
        out.reserve(at.back() + at.back() / 16);
    }
    out.resize(at.back());  // from its old size: only the growth is filled
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, 1) if (at.back() >= 16 * kThreadMin)
#endif
    for (std::size_t b = 0; b < parts.size(); ++b)
        std::copy(parts[b].begin(), parts[b].end(), out.begin() + std::ptrdiff_t(at[b]));
}

// The sums of f(i)'s K components over [0, n) in one pass, each in blocks of kSumBlock summed in
// order, the blocks then in order: the same bits at any thread count, and for each component
// the same as a pass of its own (sumIndex).
template <std::size_t K, class F>
std::array<double, K> sumsIndex(std::size_t n, F&& f) {
    const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
    std::vector<std::array<double, K>> part(blocks);
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n >= kThreadMin)  // a range of blocks each
#endif
    for (std::size_t b = 0; b < blocks; ++b) {
        std::array<double, K> s{};
        const std::size_t end = std::min(n, (b + 1) * kSumBlock);
        for (std::size_t i = b * kSumBlock; i < end; ++i) {
            const std::array<double, K> v = f(i);
            for (std::size_t k = 0; k < K; ++k) s[k] += v[k];
        }
        part[b] = s;
    }
    std::array<double, K> total{};
    for (const auto& s : part)
        for (std::size_t k = 0; k < K; ++k) total[k] += s[k];
    return total;
}

// The sum of f(i) over [0, n) in blocks of kSumBlock: the same at any thread count.
template <class F>
double sumIndex(std::size_t n, F&& f) {
    return sumsIndex<1>(n, [&](std::size_t i) { return std::array<double, 1>{f(i)}; })[0];
}

}  // namespace bop::core
