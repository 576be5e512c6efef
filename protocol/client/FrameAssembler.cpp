#include "client/FrameAssembler.hpp"

#include <algorithm>
#include <iterator>
#include <utility>

namespace bop::protocol {
namespace {

// Bytes of a frame of n particles as held in memory (what AssemblerLimits::maxPartialBytes caps),
// with normals and ids where chunk `c` has them.
std::size_t frameBytes(const StateFrame& c, std::size_t n) {
    const std::size_t perParticle = 3 * sizeof(float) * (c.normals.empty() ? 1 : 2) + sizeof(std::uint8_t) +
                                    (c.ids.empty() ? 0 : sizeof(std::uint64_t));
    return n * perParticle;
}

// Chunks of one frame repeat its header; those fields decide how the arrays fit together.
bool sameFrame(const StateFrame& a, const StateFrame& b) {
    return a.chunkCount == b.chunkCount && a.frameParticleCount == b.frameParticleCount && a.step == b.step &&
           a.encoding == b.encoding && a.normals.empty() == b.normals.empty() && a.ids.empty() == b.ids.empty();
}

void swapArrays(StateFrame& a, StateFrame& b) {
    a.positions.swap(b.positions);
    a.normals.swap(b.normals);
    a.species.swap(b.species);
    a.ids.swap(b.ids);
}

// Every field of `from` but its particle arrays into `to`, whose arrays stay as they are.
void copyHeader(StateFrame& from, StateFrame& to) {
    StateFrame fromArrays, toArrays;
    swapArrays(from, fromArrays);
    swapArrays(to, toArrays);
    to = from;
    swapArrays(from, fromArrays);
    swapArrays(to, toArrays);
}

template <class T>
void place(const std::vector<T>& from, std::vector<T>& to, std::size_t at) {
    std::copy(from.begin(), from.end(), to.begin() + std::ptrdiff_t(at));
}

}  // namespace

FrameAssembler::FrameAssembler(AssemblerLimits limits) : limits_(limits) {}

void FrameAssembler::reset() {
    for (auto it = partial_.begin(); it != partial_.end();) erase(it++, false);
    heldBytes_ = 0;
    staleRun_ = 0;
    lastDelivered_.reset();
}

void FrameAssembler::recycle(StateFrame&& frame) {
    if (frame.positions.capacity() == 0 && frame.species.capacity() == 0) return;
    spares_.push_back(std::move(frame));
    if (spares_.size() <= kMaxSpares) return;
    const auto smallest = std::min_element(
        spares_.begin(), spares_.end(),
        [](const StateFrame& a, const StateFrame& b) { return a.positions.capacity() < b.positions.capacity(); });
    spares_.erase(smallest);
}

StateFrame FrameAssembler::spare() {
    if (spares_.empty()) return {};
    const auto largest = std::max_element(spares_.begin(), spares_.end(), [](const StateFrame& a, const StateFrame& b) {
        return a.positions.capacity() < b.positions.capacity();
    });
    StateFrame f = std::move(*largest);
    spares_.erase(largest);
    return f;
}

std::optional<StateFrame> FrameAssembler::add(StateFrame chunk) {
    const std::uint64_t seq = chunk.frameSeq;
    // decodeStateFrame guarantees these; checked again as chunks may come from elsewhere.
    if (chunk.chunkCount == 0 || chunk.chunkIndex >= chunk.chunkCount ||
        std::uint64_t(chunk.firstIndex) + chunk.count() > chunk.frameParticleCount) {
        ++stats_.inconsistent;
        recycle(std::move(chunk));
        return std::nullopt;
    }
    if (lastDelivered_ && seq <= *lastDelivered_) {
        if (limits_.restartAfterStale == 0 || ++staleRun_ < limits_.restartAfterStale) {
            ++stats_.stale;
            recycle(std::move(chunk));
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
            recycle(std::move(chunk));
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

bool FrameAssembler::fits(const Partial& p, const StateFrame& chunk) const {
    if (!p.spans.empty() && !sameFrame(p.whole, chunk)) return false;
    if (p.seen[chunk.chunkIndex]) return false;  // chunkIndex < chunkCount = seen.size(), checked in add()
    // No overlap with the neighbours in frame order: the span starting at or after `first` must
    // start after it and at or after `end`; the one before must end at or before `first`.
    const std::uint32_t first = chunk.firstIndex;
    const std::uint64_t end = std::uint64_t(first) + chunk.count();
    const auto next = p.spans.lower_bound(first);
    if (next != p.spans.end() && (next->first == first || next->first < end)) return false;
    if (next != p.spans.begin()) {
        const auto prev = std::prev(next);
        if (std::uint64_t(prev->first) + prev->second > first) return false;
    }
    return true;
}

std::optional<StateFrame> FrameAssembler::addChunk(Iter it, StateFrame chunk) {
    Partial& p = it->second;
    const std::uint64_t seq = it->first;
    if (p.givenUp || !fits(p, chunk)) {
        if (!p.givenUp) ++stats_.inconsistent, giveUp(p);
        recycle(std::move(chunk));
        return std::nullopt;
    }
    const std::size_t n = chunk.frameParticleCount;
    if (p.spans.empty()) {  // the first chunk to arrive: room for the whole frame
        p.bytes = frameBytes(chunk, n);
        heldBytes_ += p.bytes;
        if (!makeRoom(seq)) {
            recycle(std::move(chunk));
            return std::nullopt;
        }
        p.whole = spare();
        copyHeader(chunk, p.whole);
        p.whole.positions.resize(3 * n);
        p.whole.normals.resize(chunk.normals.empty() ? 0 : 3 * n);
        p.whole.species.resize(n);
        p.whole.ids.resize(chunk.ids.empty() ? 0 : n);
    }
    const std::size_t first = chunk.firstIndex;
    place(chunk.positions, p.whole.positions, 3 * first);
    place(chunk.normals, p.whole.normals, 3 * first);
    place(chunk.species, p.whole.species, first);
    place(chunk.ids, p.whole.ids, first);
    p.seen[chunk.chunkIndex] = true;
    p.spans.emplace(chunk.firstIndex, std::uint32_t(chunk.count()));
    p.particles += chunk.count();
    recycle(std::move(chunk));
    if (p.spans.size() < p.whole.chunkCount) return std::nullopt;
    // Every index arrived, no two overlap and all lie inside [0, frameParticleCount): they cover it
    // exactly unless they add up to less (a gap).
    if (p.particles != n) {
        ++stats_.inconsistent;
        giveUp(p);
        return std::nullopt;
    }
    StateFrame whole = std::move(p.whole);
    whole.chunkIndex = 0;
    whole.chunkCount = 1;
    whole.firstIndex = 0;
    erase(it, false);
    return deliver(seq, std::move(whole));
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
    recycle(std::move(p.whole));
    p = Partial{};
    p.givenUp = true;
}

void FrameAssembler::erase(Iter it, bool countLost) {
    if (countLost && !it->second.givenUp) ++stats_.lost;
    heldBytes_ -= it->second.bytes;
    recycle(std::move(it->second.whole));
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
