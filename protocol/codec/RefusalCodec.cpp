// Refusal (server to client): a message refused, and why.
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "refusal_generated.h"

namespace bop::protocol {

namespace {

// One flat table with two strings; cap in DecodeResult.hpp.
const detail::MessageSpec kRefusalSpec{"Refusal", wire::RefusalIdentifier(), kMaxRefusalBytes, 4,
                                       4,         &wire::VerifyRefusalBuffer};

}  // namespace

Buffer encodeRefusal(const Refusal& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(256);
    const auto kind = fbb.CreateString(m.kind);
    const auto reason = fbb.CreateString(m.reason);
    wire::FinishRefusalBuffer(fbb, wire::CreateRefusal(fbb, kind, m.seq, reason, m.refused));
    return detail::toBuffer(fbb);
}

Decoded<Refusal> decodeRefusal(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kRefusalSpec);
    if (!vb.ok()) return detail::failed<Refusal>(vb.error(), vb.message());
    const wire::Refusal& w = *wire::GetRefusal(vb.data());
    Refusal m{detail::str(w.kind()), w.seq(), detail::str(w.reason()), w.refused()};
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
