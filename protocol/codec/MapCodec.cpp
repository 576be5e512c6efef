// MapRequest (client to server) and MapChunk (server to client): the gradient-map download.
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "map_chunk_generated.h"
#include "map_request_generated.h"

namespace bop::protocol {

namespace {

// One flat table each (the chunk's one vector is not a table); caps in DecodeResult.hpp.
const detail::MessageSpec kRequestSpec{
    "MapRequest", wire::MapRequestIdentifier(), kMaxMapRequestBytes, 4, 4, &wire::VerifyMapRequestBuffer};
const detail::MessageSpec kChunkSpec{"MapChunk", wire::MapChunkIdentifier(), kMaxMapChunkBytes, 4,
                                     4,          &wire::VerifyMapChunkBuffer};

}  // namespace

Buffer encodeMapRequest(const MapRequest& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(64);
    fbb.ForceDefaults(true);
    wire::FinishMapRequestBuffer(fbb, wire::CreateMapRequest(fbb, m.offset, m.length));
    return detail::toBuffer(fbb);
}

Decoded<MapRequest> decodeMapRequest(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kRequestSpec);
    if (!vb.ok()) return detail::failed<MapRequest>(vb.error(), vb.message());
    const wire::MapRequest& w = *wire::GetMapRequest(vb.data());
    MapRequest m{w.offset(), w.length()};
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

Buffer encodeMapChunk(const MapChunk& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(m.data.size() + 128);
    const auto data = fbb.CreateVector(m.data);
    wire::FinishMapChunkBuffer(fbb, wire::CreateMapChunk(fbb, m.offset, m.total, data));
    return detail::toBuffer(fbb);
}

Decoded<MapChunk> decodeMapChunk(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kChunkSpec);
    if (!vb.ok()) return detail::failed<MapChunk>(vb.error(), vb.message());
    const wire::MapChunk& w = *wire::GetMapChunk(vb.data());
    MapChunk m;
    m.offset = w.offset();
    m.total = w.total();
    if (const auto* d = w.data()) m.data.assign(d->begin(), d->end());
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
