#pragma once
// Internal to the codecs: the checks every decoder runs before it reads a field (size cap,
// identifier, alignment, verifier), and conversions between wire and plain types.
#include "codec/Codec.hpp"
#include "codec/Validate.hpp"
#include "common_generated.h"

#include <flatbuffers/flatbuffers.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace bop::protocol::detail {

// How to check one message type before reading it.
struct MessageSpec {
    const char* name;                        // "Probe"
    const char* identifier;                  // its file_identifier, "BPRB"
    std::size_t maxBytes;                    // cap on the whole buffer
    flatbuffers::uoffset_t maxDepth;         // nesting of tables and vectors
    flatbuffers::uoffset_t maxTables;        // tables in the buffer
    bool (*verify)(flatbuffers::Verifier&);  // generated Verify<Root>Buffer
};

// A buffer that passed the checks. data() is the caller's buffer, or an 8-byte aligned copy of
// it when the caller's was not aligned (FlatBuffers reads doubles and uint64 in place).
class VerifiedBuffer {
public:
    VerifiedBuffer(const std::uint8_t* buf, std::size_t len, const MessageSpec& spec);
    VerifiedBuffer(const VerifiedBuffer&) = delete;
    VerifiedBuffer& operator=(const VerifiedBuffer&) = delete;

    bool ok() const { return error_ == DecodeError::None; }
    DecodeError error() const { return error_; }
    const std::string& message() const { return message_; }
    const std::uint8_t* data() const { return data_; }

private:
    std::vector<std::uint64_t> copy_;
    const std::uint8_t* data_ = nullptr;
    DecodeError error_ = DecodeError::None;
    std::string message_;
};

template <class T>
Decoded<T> failed(DecodeError e, std::string message) {
    Decoded<T> d;
    d.error = e;
    d.message = std::move(message);
    return d;
}

// The decoded value if it passes validate(), else the validation's reason with the value as read
// (Decoded::read).
template <class T>
Decoded<T> accept(T value, const Validation& v) {
    Decoded<T> d = v.ok() ? Decoded<T>{} : failed<T>(v.error, v.message);
    d.read = !v.ok();
    d.value = std::move(value);
    return d;
}

// Throws EncodeError unless v.ok().
void requireValid(const Validation& v);

// Copies the finished builder's bytes out.
Buffer toBuffer(const flatbuffers::FlatBufferBuilder& fbb);

inline Eigen::Vector3d toEigen(const wire::Vec3& v) {
    return {v.x(), v.y(), v.z()};
}
inline wire::LoopStats toWire(const LoopStats& s) {
    return wire::LoopStats(s.rateHz, s.periodErrorP99Us, s.missedDeadlines);
}
inline LoopStats toLoopStats(const wire::LoopStats& s) {
    return {s.rate_hz(), s.period_error_p99_us(), s.missed_deadlines()};
}
inline wire::Vec3 toWire(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}
inline std::string str(const flatbuffers::String* s) {
    return s ? s->str() : std::string();
}

}  // namespace bop::protocol::detail
