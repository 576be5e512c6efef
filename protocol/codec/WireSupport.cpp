// Checks that run before a decoder reads anything; see WireSupport.hpp.
#include "codec/WireSupport.hpp"

#include "codec/MessageKind.hpp"

#include <cstring>

namespace bop::protocol::detail {

VerifiedBuffer::VerifiedBuffer(const std::uint8_t* buf, std::size_t len, const MessageSpec& spec) {
    const std::string name(spec.name);
    // Size first: a buffer over the cap is never read, however well formed.
    if (buf == nullptr || len < 2 * sizeof(flatbuffers::uoffset_t)) {
        error_ = DecodeError::TooShort;
        message_ = name + ": " + std::to_string(len) + " bytes, fewer than a root offset and identifier";
        return;
    }
    if (len > spec.maxBytes) {
        error_ = DecodeError::TooLarge;
        message_ = name + ": " + std::to_string(len) + " bytes, above the cap of " + std::to_string(spec.maxBytes);
        return;
    }
    if (!flatbuffers::BufferHasIdentifier(buf, spec.identifier)) {
        error_ = DecodeError::WrongIdentifier;
        message_ = name + ": file identifier is not \"" + spec.identifier + "\" (buffer holds " +
                   protocol::toString(messageKind(buf, len)) + ")";
        return;
    }
    data_ = buf;
    if (reinterpret_cast<std::uintptr_t>(buf) % alignof(std::uint64_t) != 0) {
        copy_.resize((len + 7) / 8);
        std::memcpy(copy_.data(), buf, len);
        data_ = reinterpret_cast<const std::uint8_t*>(copy_.data());
    }
    flatbuffers::Verifier::Options opts;
    opts.max_depth = spec.maxDepth;
    opts.max_tables = spec.maxTables;
    opts.check_alignment = true;
    flatbuffers::Verifier verifier(data_, len, opts);
    if (!spec.verify(verifier)) {
        error_ = DecodeError::Malformed;
        message_ = name + ": refused by the FlatBuffers verifier (bad offset, bounds, depth or table count)";
        data_ = nullptr;
    }
}

void requireValid(const Validation& v) {
    if (!v.ok()) throw EncodeError("cannot encode " + v.message);
}

Buffer toBuffer(const flatbuffers::FlatBufferBuilder& fbb) {
    const std::uint8_t* p = fbb.GetBufferPointer();
    return Buffer(p, p + fbb.GetSize());
}

}  // namespace bop::protocol::detail
