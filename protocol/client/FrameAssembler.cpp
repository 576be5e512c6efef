#include "client/FrameAssembler.hpp"

#include <iterator>
#include <utility>

namespace bop::protocol {
namespace {

// Bytes of a chunk's particle arrays as held in memory (what AssemblerLimits::maxPartialBytes caps).
std::size_t particleBytes(const StateFrame& c) {
    return (c.positions.size() + c.normals.size()) * sizeof(float) + c.species.size() +
           c.ids.size() * sizeof(std::uint64_t);
}

// Chunks of one frame repeat its header; those fields decide how the arrays fit together.
bool sameFrame(const StateFrame& a, const StateFrame& b) {
    return a.chunkCount == b.chunkCount && a.frameParticleCount == b.frameParticleCount && a.step == b.step &&
           a.encoding == b.encoding && a.normals.empty() == b.normals.empty() && a.ids.empty() == b.ids.empty();
}

template <class T>
void append(std::vector<T>& to, const std::vector<T>& from) {
    to.insert(to.end(), from.begin(), from.end());
}

}  // namespace

FrameAssembler::FrameAssembler(AssemblerLimits limits) : limits_(limits) {}

void FrameAssembler::reset() {
    partial_.clear();
    heldBytes_ = 0;
    staleRun_ = 0;
    lastDelivered_.reset();
}

std::optional<StateFrame> FrameAssembler::add(StateFrame chunk) {
    const std::uint64_t seq = chunk.frameSeq;
    // decodeStateFrame guarantees these; checked again as chunks may come from elsewhere.
    if (chunk.chunkCount == 0 || chunk.chunkIndex >= chunk.chunkCount ||
        std::uint64_t(chunk.firstIndex) + chunk.count() > chunk.frameParticleCount) {
        ++stats_.inconsistent;
        return std::nullopt;
    }
    if (lastDelivered_ && seq <= *lastDelivered_) {
        if (limits_.restartAfterStale == 0 || ++staleRun_ < limits_.restartAfterStale) {
            ++stats_.stale;
            return std::nullopt;
        }
        ++stats_.restarts;  // this chunk starts the new numbering
        reset();
    }
    staleRun_ = 0;
    const auto it = partial_.find(seq);
    if (chunk.chunkCount == 1 && it == partial_.end()) {
        // A whole frame in one chunk (the usual case): no bookkeeping. The decoder checked
        // firstIndex + count <= frameParticleCount; a whole frame must start at 0 and fill it.
        if (chunk.firstIndex != 0 || chunk.count() != chunk.frameParticleCount) {
            ++stats_.inconsistent;
            return std::nullopt;
        }
        return deliver(seq, std::move(chunk));
    }
    if (it != partial_.end()) return addChunk(it, std::move(chunk));
    const std::uint32_t count = chunk.chunkCount;
    const Iter fresh = partial_.try_emplace(seq).first;
    fresh->second.seen.assign(count, false);
    return addChunk(fresh, std::move(chunk));
}

std::optional<StateFrame> FrameAssembler::addChunk(Iter it, StateFrame chunk) {
    Partial& p = it->second;
    if (p.givenUp) return std::nullopt;
    const std::uint32_t first = chunk.firstIndex;
    const std::uint64_t end = std::uint64_t(first) + chunk.count();
    bool fits = p.chunks.empty() || sameFrame(p.chunks.begin()->second, chunk);
    fits = fits && !p.seen[chunk.chunkIndex];  // chunkIndex < chunkCount, checked in add()
    if (fits) {
        // No overlap with the neighbours in frame order: the chunk starting at or after `first`
        // must start after it and at or after `end`; the one before must end at or before `first`.
        const auto next = p.chunks.lower_bound(first);
        if (next != p.chunks.end() && (next->first == first || next->first < end)) fits = false;
        if (next != p.chunks.begin()) {
            const StateFrame& prev = std::prev(next)->second;
            if (std::uint64_t(prev.firstIndex) + prev.count() > first) fits = false;
        }
    }
    if (!fits) {
        ++stats_.inconsistent;
        giveUp(p);
        return std::nullopt;
    }
    const std::size_t bytes = particleBytes(chunk);
    p.seen[chunk.chunkIndex] = true;
    p.bytes += bytes;
    p.particles += chunk.count();
    heldBytes_ += bytes;
    const std::uint32_t chunkCount = chunk.chunkCount;
    p.chunks.emplace(first, std::move(chunk));
    if (!makeRoom(it->first)) return std::nullopt;
    if (p.chunks.size() < chunkCount) return std::nullopt;
    // Every index arrived, no two overlap and all lie inside [0, frameParticleCount): they cover it
    // exactly unless they add up to less (a gap).
    if (p.particles != p.chunks.begin()->second.frameParticleCount) {
        ++stats_.inconsistent;
        giveUp(p);
        return std::nullopt;
    }
    StateFrame whole = concatenate(p);
    const std::uint64_t seq = it->first;
    erase(it, false);
    return deliver(seq, std::move(whole));
}

StateFrame FrameAssembler::concatenate(Partial& p) {
    StateFrame whole = std::move(p.chunks.begin()->second);
    const std::size_t n = whole.frameParticleCount;
    whole.positions.reserve(3 * n);
    whole.species.reserve(n);
    if (!whole.normals.empty()) whole.normals.reserve(3 * n);
    if (!whole.ids.empty()) whole.ids.reserve(n);
    for (auto c = std::next(p.chunks.begin()); c != p.chunks.end(); ++c) {
        append(whole.positions, c->second.positions);
        append(whole.normals, c->second.normals);
        append(whole.species, c->second.species);
        append(whole.ids, c->second.ids);
    }
    whole.chunkIndex = 0;
    whole.chunkCount = 1;
    whole.firstIndex = 0;
    return whole;
}

std::optional<StateFrame> FrameAssembler::deliver(std::uint64_t seq, StateFrame frame) {
    // Newest wins: whatever is older and still incomplete will never be shown.
    while (!partial_.empty() && partial_.begin()->first < seq) erase(partial_.begin(), true);
    lastDelivered_ = seq;
    ++stats_.delivered;
    return frame;
}

void FrameAssembler::giveUp(Partial& p) {
    heldBytes_ -= p.bytes;
    p = Partial{};
    p.givenUp = true;
}

void FrameAssembler::erase(Iter it, bool countLost) {
    if (countLost && !it->second.givenUp) ++stats_.lost;
    heldBytes_ -= it->second.bytes;
    partial_.erase(it);
}

bool FrameAssembler::makeRoom(std::uint64_t seq) {
    while (partial_.size() > limits_.maxPartialFrames || heldBytes_ > limits_.maxPartialBytes) {
        const Iter oldest = partial_.begin();
        if (oldest->first == seq) {
            // The frame being added is the oldest: it goes, as a tombstone so that its remaining
            // chunks do not start it again (a later frame's eviction removes the tombstone).
            ++stats_.lost;
            giveUp(oldest->second);
            return false;
        }
        erase(oldest, true);
    }
    return true;
}

}  // namespace bop::protocol
