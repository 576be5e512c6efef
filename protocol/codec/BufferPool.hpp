#pragma once
// Buffers kept for reuse, from any thread. A sender streaming large frames gives each buffer back
// once its bytes are gone (ZeroMQ frees a zero-copy message from its I/O thread) and encodes the
// next frame into it: writing into fresh memory costs more than encoding a large frame.
#include "codec/Codec.hpp"

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

namespace bop::protocol {

class BufferPool {
public:
    explicit BufferPool(std::size_t keep) : keep_(keep) {}

    // The largest kept buffer, empty but with its capacity, or a new one.
    Buffer take() {
        std::lock_guard lock(m_);
        if (kept_.empty()) return {};
        const auto largest = std::max_element(
            kept_.begin(), kept_.end(), [](const Buffer& a, const Buffer& b) { return a.capacity() < b.capacity(); });
        Buffer b = std::move(*largest);
        kept_.erase(largest);
        b.clear();
        return b;
    }
    // Kept if fewer than `keep` are; else freed.
    void give(Buffer&& b) {
        std::lock_guard lock(m_);
        if (kept_.size() < keep_ && b.capacity() > 0) kept_.push_back(std::move(b));
    }
    std::size_t kept() const {
        std::lock_guard lock(m_);
        return kept_.size();
    }

private:
    const std::size_t keep_;
    mutable std::mutex m_;
    std::vector<Buffer> kept_;
};

}  // namespace bop::protocol
