// Probe (client to server, up to 1 kHz) and Feedback (server to client, every step).
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "feedback_generated.h"
#include "probe_generated.h"

namespace bop::protocol {

namespace {

// Both are one flat table: depth 1, one table; caps in DecodeResult.hpp.
const detail::MessageSpec kProbeSpec{"Probe", wire::ProbeIdentifier(), kMaxProbeBytes, 4, 4, &wire::VerifyProbeBuffer};
const detail::MessageSpec kFeedbackSpec{"Feedback", wire::FeedbackIdentifier(), kMaxFeedbackBytes, 4,
                                        4,          &wire::VerifyFeedbackBuffer};

}  // namespace

Buffer encodeProbe(const Probe& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(128);
    const wire::Vec3 position = detail::toWire(m.position);
    // force_defaults: k0 and k1 are written even when they equal the schema default, so the
    // size of a probe does not depend on its values.
    fbb.ForceDefaults(true);
    const wire::LoopStats loop = detail::toWire(m.loop);
    const wire::Vec3 rendered = detail::toWire(m.renderedForce);
    wire::FinishProbeBuffer(
        fbb, wire::CreateProbe(fbb, m.seq, m.clientTimeNs, &position, m.active, m.k0, m.k1, &loop, &rendered));
    return detail::toBuffer(fbb);
}

Decoded<Probe> decodeProbe(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kProbeSpec);
    if (!vb.ok()) return detail::failed<Probe>(vb.error(), vb.message());
    const wire::Probe& w = *wire::GetProbe(vb.data());
    if (w.position() == nullptr) return detail::failed<Probe>(DecodeError::MissingField, "Probe.position: absent");
    Probe m;
    m.seq = w.seq();
    m.clientTimeNs = w.client_time_ns();
    m.position = detail::toEigen(*w.position());
    m.active = w.active();
    m.k0 = w.k0();
    m.k1 = w.k1();
    if (const wire::LoopStats* loop = w.loop()) m.loop = detail::toLoopStats(*loop);
    if (const wire::Vec3* f = w.rendered_force()) m.renderedForce = detail::toEigen(*f);
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

Buffer encodeFeedback(const Feedback& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(128);
    fbb.ForceDefaults(true);
    const wire::Vec3 force = detail::toWire(m.force);
    wire::FinishFeedbackBuffer(fbb, wire::CreateFeedback(fbb, m.probeSeq, m.step, &force, m.serverTimeNs, m.mapEdits));
    return detail::toBuffer(fbb);
}

Decoded<Feedback> decodeFeedback(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kFeedbackSpec);
    if (!vb.ok()) return detail::failed<Feedback>(vb.error(), vb.message());
    const wire::Feedback& w = *wire::GetFeedback(vb.data());
    if (w.force() == nullptr) return detail::failed<Feedback>(DecodeError::MissingField, "Feedback.force: absent");
    Feedback m;
    m.probeSeq = w.probe_seq();
    m.step = w.step();
    m.force = detail::toEigen(*w.force());
    m.serverTimeNs = w.server_time_ns();
    m.mapEdits = w.map_edits();
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
