// MapEditsRequest (client to server) and MapEdits (server to client): the gradient map's edits,
// for a haptic client's copy.
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "map_edits_generated.h"
#include "map_edits_request_generated.h"

#include <cstring>

namespace bop::protocol {

namespace {

// The request is one flat table; the answer a table holding a vector of tables (depth 3), one
// table per edit and the root.
const detail::MessageSpec kRequestSpec{"MapEditsRequest",
                                       wire::MapEditsRequestIdentifier(),
                                       kMaxMapEditsRequestBytes,
                                       4,
                                       4,
                                       &wire::VerifyMapEditsRequestBuffer};
const detail::MessageSpec kEditsSpec{"MapEdits", wire::MapEditsIdentifier(), kMaxMapEditsBytes,
                                     8,          kMaxEditsPerMessage + 4,    &wire::VerifyMapEditsBuffer};

}  // namespace

Buffer encodeMapEditsRequest(const MapEditsRequest& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(64);
    fbb.ForceDefaults(true);
    wire::FinishMapEditsRequestBuffer(fbb, wire::CreateMapEditsRequest(fbb, m.first));
    return detail::toBuffer(fbb);
}

Decoded<MapEditsRequest> decodeMapEditsRequest(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kRequestSpec);
    if (!vb.ok()) return detail::failed<MapEditsRequest>(vb.error(), vb.message());
    MapEditsRequest m{wire::GetMapEditsRequest(vb.data())->first()};
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

Buffer encodeMapEdits(const MapEdits& m) {
    detail::requireValid(validate(m));
    std::size_t voxels = 0;
    for (const MapEdit& e : m.edits) voxels += e.voxels.size();
    flatbuffers::FlatBufferBuilder fbb(8 * voxels + 96 * m.edits.size() + 128);
    std::vector<flatbuffers::Offset<wire::MapEdit>> edits;
    edits.reserve(m.edits.size());
    for (const MapEdit& e : m.edits) {
        const wire::Vec3 from = detail::toWire(e.cut.from), to = detail::toWire(e.cut.to);
        const auto list = e.voxels.empty() ? 0 : fbb.CreateVector(e.voxels);
        edits.push_back(wire::CreateMapEdit(fbb, &from, &to, e.cut.radius, list));
    }
    const auto vec = fbb.CreateVector(edits);
    wire::FinishMapEditsBuffer(fbb, wire::CreateMapEdits(fbb, m.first, m.total, vec));
    return detail::toBuffer(fbb);  // within kMaxMapEditsBytes: validate() bounds the edits' bytes
}

Decoded<MapEdits> decodeMapEdits(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kEditsSpec);
    if (!vb.ok()) return detail::failed<MapEdits>(vb.error(), vb.message());
    const wire::MapEdits& w = *wire::GetMapEdits(vb.data());
    MapEdits m;
    m.first = w.first();
    m.total = w.total();
    if (const auto* edits = w.edits()) {
        if (edits->size() > kMaxEditsPerMessage)
            return detail::failed<MapEdits>(DecodeError::BadLength, "MapEdits.edits: " + std::to_string(edits->size()) +
                                                                        " edits, at most " +
                                                                        std::to_string(kMaxEditsPerMessage));
        // Before copying: edits may share one voxel vector, so the buffer's size bounds nothing.
        std::size_t bytes = 0;
        for (const wire::MapEdit* e : *edits) bytes += mapEditWireBytes(e->voxels() ? e->voxels()->size() : 0);
        if (bytes > kMaxMapEditsPayload)
            return detail::failed<MapEdits>(DecodeError::TooLarge, "MapEdits.edits: about " + std::to_string(bytes) +
                                                                       " bytes of edits, at most " +
                                                                       std::to_string(kMaxMapEditsPayload));
        m.edits.reserve(edits->size());
        for (const wire::MapEdit* e : *edits) {
            if (e->from() == nullptr || e->to() == nullptr)
                return detail::failed<MapEdits>(DecodeError::MissingField, "MapEdits.edits.from, .to: absent");
            MapEdit& out = m.edits.emplace_back();
            out.cut = {detail::toEigen(*e->from()), detail::toEigen(*e->to()), e->radius()};
            if (const auto* v = e->voxels(); v && v->size() > 0) {  // 8-byte values may sit 4 bytes off
                out.voxels.resize(v->size());
                std::memcpy(out.voxels.data(), v->Data(), 8 * out.voxels.size());
            }
        }
    }
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
