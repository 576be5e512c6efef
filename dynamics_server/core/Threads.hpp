#pragma once
// Threads inside a process (OpenMP from the compiler): loops whose results do not depend on the
// number of threads. A per-particle loop writes only its particle's values; a sum runs over
// fixed blocks of kSumBlock items, each summed in order, and the block sums in order, so that the
// same bits come out at 1, 2 or 16 threads. Without OpenMP the loops run on the calling thread.
#include <algorithm>
#include <cstddef>
#include <vector>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace bop::core {

inline constexpr std::size_t kSumBlock = 256;   // items per block of a sum
inline constexpr std::size_t kThreadMin = 256;  // loops shorter than this stay on one thread
// Per-particle loops deal the particles to the threads in turns of this many: a bag's particles
// come species by species, and a surface particle costs more than a volume one (its rotation,
// its normal's map sample), so halves would leave one thread most of the work.
inline constexpr std::size_t kIndexTurn = 64;

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

// f(i) for i in [0, n), on the threads (in turns of kIndexTurn).
template <class F>
void forEachIndex(std::size_t n, F&& f) {
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, kIndexTurn) if (n >= kThreadMin)
#endif
    for (std::size_t i = 0; i < n; ++i) f(i);
}

// The number of blocks of `block` items that cover [0, n).
inline std::size_t blockCount(std::size_t n, std::size_t block) {
    return (n + block - 1) / block;
}

// f(b, begin, end) for each block b = [b * block, min(n, (b + 1) * block)) of [0, n), on the
// threads (dynamic schedule, `grain` blocks at a time) when `threaded` and there are several.
// The blocks depend on n and block alone: a caller that keeps each block's results and joins
// them in block order gets the same bits at any thread count.
template <class F>
void forBlocks(std::size_t n, std::size_t block, F&& f, std::size_t grain = 1, bool threaded = true) {
    const std::size_t blocks = blockCount(n, block);
#if defined(_OPENMP)
#pragma omp parallel for schedule(dynamic, grain) if (threaded && blocks > 1)
#endif
    for (std::size_t b = 0; b < blocks; ++b) f(b, b * block, std::min(n, (b + 1) * block));
}

// The sum of f(i) over [0, n) in blocks of kSumBlock: the same at any thread count.
template <class F>
double sumIndex(std::size_t n, F&& f) {
    const std::size_t blocks = (n + kSumBlock - 1) / kSumBlock;
    std::vector<double> part(blocks, 0.0);
#if defined(_OPENMP)
#pragma omp parallel for schedule(static, 1) if (n >= kThreadMin)  // blocks dealt in turns
#endif
    for (std::size_t b = 0; b < blocks; ++b) {
        double s = 0;
        const std::size_t end = std::min(n, (b + 1) * kSumBlock);
        for (std::size_t i = b * kSumBlock; i < end; ++i) s += f(i);
        part[b] = s;
    }
    double total = 0;
    for (double s : part) total += s;
    return total;
}

}  // namespace bop::core
