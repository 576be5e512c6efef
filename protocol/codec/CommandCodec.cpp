// Command (client to server) and CommandReply (server to client), request/reply.
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "command_generated.h"
#include "reply_generated.h"

#include <utility>
#include <variant>

namespace bop::protocol {

namespace {

// Command: the root table and one body table; reply: one table.
const detail::MessageSpec kCommandSpec{"Command", wire::CommandIdentifier(), kMaxCommandBytes, 4,
                                       4,         &wire::VerifyCommandBuffer};
const detail::MessageSpec kReplySpec{
    "CommandReply", wire::CommandReplyIdentifier(), kMaxReplyBytes, 4, 4, &wire::VerifyCommandReplyBuffer};

using Body = std::pair<wire::CommandBody, flatbuffers::Offset<void>>;

Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const SeedParticle& b) {
    const wire::Vec3 p = detail::toWire(b.position);
    return {wire::CommandBody::SeedParticle, wire::CreateSeedParticle(fbb, std::uint8_t(b.species), &p).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const SetBirth& b) {
    return {wire::CommandBody::SetBirth, wire::CreateSetBirth(fbb, std::uint8_t(b.species), b.enabled).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const SetParameter& b) {
    return {wire::CommandBody::SetParameter,
            wire::CreateSetParameter(fbb, fbb.CreateString(b.name), std::uint8_t(b.speciesA), std::uint8_t(b.speciesB),
                                     b.value)
                .Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const RunControl& b) {
    return {wire::CommandBody::RunControl, wire::CreateRunControl(fbb, wire::RunAction(b.action), b.steps).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const SwitchMapFrame& b) {
    return {wire::CommandBody::SwitchMapFrame, wire::CreateSwitchMapFrame(fbb, b.frame).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const Checkpoint& b) {
    return {wire::CommandBody::Checkpoint, wire::CreateCheckpoint(fbb, fbb.CreateString(b.path)).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const Record& b) {
    return {wire::CommandBody::Record, wire::CreateRecord(fbb, b.start, fbb.CreateString(b.path)).Union()};
}
Body writeBody(flatbuffers::FlatBufferBuilder& fbb, const Cut& b) {
    const wire::Vec3 from = detail::toWire(b.from), to = detail::toWire(b.to);
    return {wire::CommandBody::Cut, wire::CreateCut(fbb, &from, &to, b.radius).Union()};
}

// The plain body of a verified command, or a failure naming why there is none.
Decoded<CommandBody> readBody(const wire::Command& w) {
    using detail::failed;
    Decoded<CommandBody> out;
    switch (w.body_type()) {
        case wire::CommandBody::NONE:
            break;
        case wire::CommandBody::SeedParticle: {
            const auto* b = w.body_as_SeedParticle();
            if (b == nullptr || b->position() == nullptr)
                return failed<CommandBody>(DecodeError::MissingField, "Command.SeedParticle.position: absent");
            out.value = SeedParticle{b->species(), detail::toEigen(*b->position())};
            return out;
        }
        case wire::CommandBody::SetBirth:
            if (const auto* b = w.body_as_SetBirth()) {
                out.value = SetBirth{b->species(), b->enabled()};
                return out;
            }
            break;
        case wire::CommandBody::SetParameter:
            if (const auto* b = w.body_as_SetParameter()) {
                out.value = SetParameter{detail::str(b->name()), b->species_a(), b->species_b(), b->value()};
                return out;
            }
            break;
        case wire::CommandBody::RunControl:
            if (const auto* b = w.body_as_RunControl()) {
                out.value = RunControl{RunAction(b->action()), b->steps()};
                return out;
            }
            break;
        case wire::CommandBody::SwitchMapFrame:
            if (const auto* b = w.body_as_SwitchMapFrame()) {
                out.value = SwitchMapFrame{b->frame()};
                return out;
            }
            break;
        case wire::CommandBody::Checkpoint:
            if (const auto* b = w.body_as_Checkpoint()) {
                out.value = Checkpoint{detail::str(b->path())};
                return out;
            }
            break;
        case wire::CommandBody::Record:
            if (const auto* b = w.body_as_Record()) {
                out.value = Record{b->start(), detail::str(b->path())};
                return out;
            }
            break;
        case wire::CommandBody::Cut: {
            const auto* b = w.body_as_Cut();
            if (b == nullptr || b->from() == nullptr || b->to() == nullptr)
                return failed<CommandBody>(DecodeError::MissingField, "Command.Cut.from, .to: absent");
            out.value = Cut{detail::toEigen(*b->from()), detail::toEigen(*b->to()), b->radius()};
            return out;
        }
        default:
            return failed<CommandBody>(DecodeError::Unsupported,
                                       "Command.body: unknown command type " + std::to_string(int(w.body_type())));
    }
    return failed<CommandBody>(DecodeError::MissingField, "Command.body: absent");
}

}  // namespace

Buffer encodeCommand(const Command& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(256);
    const Body body = std::visit([&fbb](const auto& b) { return writeBody(fbb, b); }, m.body);
    wire::FinishCommandBuffer(fbb, wire::CreateCommand(fbb, m.requestId, body.first, body.second));
    return detail::toBuffer(fbb);
}

Decoded<Command> decodeCommand(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kCommandSpec);
    if (!vb.ok()) return detail::failed<Command>(vb.error(), vb.message());
    const wire::Command& w = *wire::GetCommand(vb.data());
    Decoded<CommandBody> body = readBody(w);
    if (!body.ok()) {  // the request id was read: the refusal can name the request
        Decoded<Command> d = detail::failed<Command>(body.error, body.message);
        d.read = true;
        d.value.requestId = w.request_id();
        return d;
    }
    Command m{w.request_id(), std::move(body.value)};
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

Buffer encodeCommandReply(const CommandReply& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(256);
    const auto message = fbb.CreateString(m.message);
    wire::FinishCommandReplyBuffer(
        fbb, wire::CreateCommandReply(fbb, m.requestId, wire::ReplyStatus(m.status), m.step, message));
    return detail::toBuffer(fbb);
}

Decoded<CommandReply> decodeCommandReply(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kReplySpec);
    if (!vb.ok()) return detail::failed<CommandReply>(vb.error(), vb.message());
    const wire::CommandReply& w = *wire::GetCommandReply(vb.data());
    CommandReply m{w.request_id(), ReplyStatus(w.status()), w.step(), detail::str(w.message())};
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
