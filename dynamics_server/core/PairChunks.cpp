#include "PairChunks.hpp"

#include "Threads.hpp"

#include <algorithm>
#include <chrono>

namespace bop::core {
namespace {

constexpr double kChunkWork = 4000;  // listed pairs per chunk, an oriented one counting 3
constexpr std::size_t kMaxChunks = 64;
// Fewer chunks (down to kMinChunks) when their buffers would hold more than kMaxBuffer entries per
// list entry: a buffer reaches past its rows by about two planes of cells (the wide pairs' range),
// and zeroing and summing that spill cost more than the loops gain from the extra pieces.
constexpr std::size_t kMinChunks = 4;
constexpr double kMaxBuffer = 3.0;
using Clock = std::chrono::steady_clock;

// The largest neighbour in rows [x0, x1) of p, or 0.
std::uint32_t farthest(const NeighbourList::Pairs& p, std::uint32_t x0, std::uint32_t x1) {
    std::uint32_t hi = 0;
    if (p.start.size() < 2) return hi;
    for (std::uint32_t k = p.start[x0]; k < p.start[x1]; ++k) hi = std::max(hi, p.nbr[k]);
    return hi;
}

std::size_t rowLength(const NeighbourList::Pairs& p, std::size_t x) {
    return p.start.size() < 2 ? 0 : p.start[x + 1] - p.start[x];
}

}  // namespace

void PairChunks::plan(const NeighbourList& list, bool oriented) {
    oriented_ = oriented;
    const std::size_t ne = list.entryCount();
    const auto work = [&](std::size_t x) {
        double w = double(rowLength(list.pairs(), x) + rowLength(list.haloPairs(), x));
        if (oriented) w += 3.0 * double(rowLength(list.widePairs(), x) + rowLength(list.wideHaloPairs(), x));
        return w + 1.0;
    };
    double total = 0;
    for (std::size_t x = 0; x < ne; ++x) total += work(x);
    std::size_t count = std::clamp<std::size_t>(std::size_t(total / kChunkWork), 1, kMaxChunks);
    std::size_t offset = cut(list, count, total, work);
    if (double(offset) > kMaxBuffer * double(ne) && count > kMinChunks) {
        const double spill = double(offset - ne) / double(count);  // per chunk, past its rows
        count = std::clamp<std::size_t>(std::size_t((kMaxBuffer - 1.0) * double(ne) / spill), kMinChunks, count);
        offset = cut(list, count, total, work);
    }
    bf_.resize(offset);
    if (oriented) bt_.resize(offset);
    sums_.resize(chunks_.size());
    ljSeconds_.resize(chunks_.size());
    orientedSeconds_.resize(chunks_.size());
    haloSums_.resize(chunks_.size());
}

template <typename Work>
std::size_t PairChunks::cut(const NeighbourList& list, std::size_t count, double total, const Work& work) {
    const std::size_t ne = list.entryCount();
    chunks_.clear();
    double done = 0;
    Chunk c;
    for (std::size_t x = 0; x < ne; ++x) {
        done += work(x);
        const bool last = x + 1 == ne;
        if (!last && done < total * double(chunks_.size() + 1) / double(count)) continue;
        c.x1 = std::uint32_t(x + 1);
        chunks_.push_back(c);
        c.x0 = c.x1;
    }
    forBlocks(chunks_.size(), 1, [&](std::size_t k, std::size_t, std::size_t) {  // each chunk's reach, on the threads
        Chunk& ch = chunks_[k];
        std::uint32_t hi = ch.x1 > 0 ? ch.x1 - 1 : 0;
        hi = std::max({hi, farthest(list.pairs(), ch.x0, ch.x1), farthest(list.haloPairs(), ch.x0, ch.x1)});
        if (oriented_)
            hi = std::max({hi, farthest(list.widePairs(), ch.x0, ch.x1), farthest(list.wideHaloPairs(), ch.x0, ch.x1)});
        ch.hi = hi + 1;
    });
    std::size_t offset = 0;
    for (std::size_t k = 0; k < chunks_.size(); ++k) {
        Chunk& ch = chunks_[k];
        ch.offset = offset;
        offset += ch.hi - ch.x0;
        ch.firstCover = std::uint32_t(k);
        while (ch.firstCover > 0 && chunks_[ch.firstCover - 1].hi > ch.x0) --ch.firstCover;
        // An earlier chunk may reach past a later one's start without its neighbour doing so.
        for (std::uint32_t j = 0; j < ch.firstCover; ++j)
            if (chunks_[j].hi > ch.x0) ch.firstCover = j;
    }
    return offset;
}

void PairChunks::run(const PairKernel& kernel, const PrunedPairs::Sets& sets, PairInputs in, OrientedInputs o,
                     bool energies, bool halo, PairKernel::Sums& sums, PairKernel::Sums& haloSums, double seconds[2],
                     ParticleTargets into) {
    Eigen::Vector3d* f = in.f;
    Eigen::Vector3d* t = o.t;
    const std::size_t n = chunks_.size();
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n > 1)  // a range of chunks each, as the particles
#endif
    for (std::size_t k = 0; k < n; ++k) {
        const Chunk& c = chunks_[k];
        PairInputs ci = in;
        ci.f = bf_.data() + c.offset;
        ci.base = c.x0;
        OrientedInputs co = o;
        std::fill(ci.f, ci.f + (c.hi - c.x0), Eigen::Vector3d::Zero());
        if (oriented_) {
            co.t = bt_.data() + c.offset;
            std::fill(co.t, co.t + (c.hi - c.x0), Eigen::Vector3d::Zero());
        }
        PairKernel::Sums s, h;
        const auto t0 = Clock::now();
        ljForcePairs(kernel, *sets.lj, ci, energies, c.x0, c.x1, s);
        if (halo) ljForcePairs(kernel, *sets.ljHalo, ci, energies, c.x0, c.x1, h);
        const auto t1 = Clock::now();
        if (oriented_) {
            orientedPairs(kernel, *sets.wide, ci, co, energies, c.x0, c.x1, s);
            if (halo) orientedPairs(kernel, *sets.wideHalo, ci, co, energies, c.x0, c.x1, h);
        }
        ljSeconds_[k] = std::chrono::duration<double>(t1 - t0).count();
        orientedSeconds_[k] = std::chrono::duration<double>(Clock::now() - t1).count();
        sums_[k] = s;
        haloSums_[k] = h;
    }
    // Entry by entry, the chunks that reach it, in chunk order.
#if defined(_OPENMP)
#pragma omp parallel for schedule(static) if (n > 1)
#endif
    for (std::size_t k = 0; k < n; ++k) {
        const Chunk& own = chunks_[k];
        for (std::uint32_t e = own.x0; e < own.x1; ++e) {
            Eigen::Vector3d fe = Eigen::Vector3d::Zero(), te = Eigen::Vector3d::Zero();
            for (std::uint32_t j = own.firstCover; j <= k; ++j) {
                const Chunk& c = chunks_[j];
                if (e >= c.hi) continue;
                fe += bf_[c.offset + (e - c.x0)];
                if (oriented_) te += bt_[c.offset + (e - c.x0)];
            }
            if (into.force) {
                into.force[into.owner[e]] += fe;
                if (oriented_) into.torque[into.owner[e]] += te;
            } else {
                f[e] = fe;
                if (oriented_) t[e] = te;
            }
        }
    }
    for (std::size_t k = 0; k < n; ++k) {
        seconds[0] += ljSeconds_[k];
        seconds[1] += orientedSeconds_[k];
        for (auto [to, from] : {std::pair{&sums, &sums_[k]}, std::pair{&haloSums, &haloSums_[k]}}) {
            to->energy += from->energy;
            to->virial += from->virial;
            to->virialVolume += from->virialVolume;
            to->inRange += from->inRange;
            to->orientedInRange += from->orientedInRange;
        }
    }
}

}  // namespace bop::core
