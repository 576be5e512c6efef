// Hello (client to server) and SceneInfo (the server's answer).
#include "codec/Codec.hpp"
#include "codec/WireSupport.hpp"
#include "hello_generated.h"
#include "scene_generated.h"

#include <bit>
#include <cstring>

static_assert(std::endian::native == std::endian::little, "FlatBuffers vectors are copied as they lie");

namespace bop::protocol {

namespace {

// Hello is one table; SceneInfo holds up to 255 Species tables and an Endpoints table.
const detail::MessageSpec kHelloSpec{"Hello", wire::HelloIdentifier(), kMaxHelloBytes, 4, 4, &wire::VerifyHelloBuffer};
const detail::MessageSpec kSceneSpec{"SceneInfo",     wire::SceneInfoIdentifier(), kMaxSceneInfoBytes, 8,
                                     kMaxSpecies + 8, &wire::VerifySceneInfoBuffer};

}  // namespace

Buffer encodeHello(const Hello& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(256);
    const auto name = fbb.CreateString(m.clientName);
    wire::HelloBuilder b(fbb);
    b.add_protocol_version(m.protocolVersion);
    b.add_role(wire::Role(m.role));
    b.add_frame_rate_hz(m.frameRateHz);
    b.add_read_only(m.readOnly);
    b.add_client_name(name);
    b.add_udp_frame_port(m.udpFramePort);
    wire::FinishHelloBuffer(fbb, b.Finish());
    return detail::toBuffer(fbb);
}

Decoded<Hello> decodeHello(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kHelloSpec);
    if (!vb.ok()) return detail::failed<Hello>(vb.error(), vb.message());
    const wire::Hello& w = *wire::GetHello(vb.data());
    Hello m;
    m.protocolVersion = w.protocol_version();
    m.role = Role(w.role());
    m.frameRateHz = w.frame_rate_hz();
    m.readOnly = w.read_only();
    m.clientName = detail::str(w.client_name());
    m.udpFramePort = w.udp_frame_port();
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

Buffer encodeSceneInfo(const SceneInfo& m) {
    detail::requireValid(validate(m));
    flatbuffers::FlatBufferBuilder fbb(1024);
    std::vector<flatbuffers::Offset<wire::Species>> species;
    for (const SpeciesInfo& s : m.species) {
        const wire::Rgba8 colour(s.rgba[0], s.rgba[1], s.rgba[2], s.rgba[3]);
        const auto name = fbb.CreateString(s.name);  // by size: a name may hold any byte
        species.push_back(wire::CreateSpecies(fbb, name, wire::SpeciesKind(s.kind), &colour));
    }
    const auto speciesVec = fbb.CreateVector(species);
    const auto frameEndpoint = fbb.CreateString(m.endpoints.frameEndpoint);
    const auto endpoints =
        wire::CreateEndpoints(fbb, frameEndpoint, m.endpoints.udpFramePort, m.endpoints.udpProbePort);
    const auto units = fbb.CreateString(m.units);
    const Tunables& t = m.tunables;
    const auto tunables =
        wire::CreateTunables(fbb, fbb.CreateVector(t.lj), fbb.CreateVector(t.coNormal), fbb.CreateVector(t.coPlanar),
                             fbb.CreateVector(t.dragV), fbb.CreateVector(t.dragW), t.k0, t.k1);
    const wire::Vec3 lo = detail::toWire(m.boxLo), hi = detail::toWire(m.boxHi);
    const wire::Vec3 origin = detail::toWire(m.gridOriginMm);
    const wire::Int3 dims(m.gridDims[0], m.gridDims[1], m.gridDims[2]);
    wire::SceneInfoBuilder b(fbb);
    b.add_protocol_version(m.protocolVersion);
    b.add_species(speciesVec);
    b.add_box_lo(&lo);
    b.add_box_hi(&hi);
    b.add_grid_origin_mm(&origin);
    b.add_grid_dims(&dims);
    b.add_voxel_size_mm(m.voxelSizeMm);
    b.add_r0(m.r0);  // left out when it equals the schema default, sqrt 3, and read back as such
    b.add_r0_voxels(m.r0Voxels);
    b.add_dt(m.dt);
    b.add_endpoints(endpoints);
    b.add_particle_count(m.particleCount);
    b.add_units(units);
    b.add_publish_rate_hz(m.publishRateHz);
    b.add_probe_reach(m.probeReach);
    b.add_tunables(tunables);
    b.add_map_bytes(m.mapBytes);
    b.add_map_key(m.mapKey);
    b.add_session_timeout_s(m.sessionTimeoutS);
    b.add_length_mm(m.unitSystem.lengthMm);
    b.add_mass_kg(m.unitSystem.massKg);
    b.add_time_s(m.unitSystem.timeS);
    b.add_force_n(m.unitSystem.physical ? m.unitSystem.forceN() : 0.0);
    b.add_physical_units(m.unitSystem.physical);
    wire::FinishSceneInfoBuffer(fbb, b.Finish());
    return detail::toBuffer(fbb);
}

Decoded<SceneInfo> decodeSceneInfo(const std::uint8_t* buf, std::size_t len) {
    const detail::VerifiedBuffer vb(buf, len, kSceneSpec);
    if (!vb.ok()) return detail::failed<SceneInfo>(vb.error(), vb.message());
    const wire::SceneInfo& w = *wire::GetSceneInfo(vb.data());
    if (!w.box_lo() || !w.box_hi())
        return detail::failed<SceneInfo>(DecodeError::MissingField, "SceneInfo.box_lo/box_hi: absent");
    SceneInfo m;
    m.protocolVersion = w.protocol_version();
    if (const auto* species = w.species()) {
        if (species->size() > std::size_t(kMaxSpecies))
            return detail::failed<SceneInfo>(DecodeError::BadLength, "SceneInfo.species: more than 255 entries");
        for (const wire::Species* s : *species) {
            SpeciesInfo info;
            info.name = detail::str(s->name());
            info.kind = SpeciesKind(s->kind());
            if (const wire::Rgba8* c = s->colour()) info.rgba = {c->r(), c->g(), c->b(), c->a()};
            m.species.push_back(std::move(info));
        }
    }
    m.boxLo = detail::toEigen(*w.box_lo());
    m.boxHi = detail::toEigen(*w.box_hi());
    m.gridOriginMm = w.grid_origin_mm() ? detail::toEigen(*w.grid_origin_mm()) : Eigen::Vector3d::Zero();
    if (const wire::Int3* d = w.grid_dims()) m.gridDims = {d->x(), d->y(), d->z()};
    m.voxelSizeMm = w.voxel_size_mm();
    m.r0 = w.r0();
    m.r0Voxels = w.r0_voxels();
    m.dt = w.dt();
    if (const wire::Endpoints* e = w.endpoints()) {
        m.endpoints.frameEndpoint = detail::str(e->frame_endpoint());
        m.endpoints.udpFramePort = e->udp_frame_port();
        m.endpoints.udpProbePort = e->udp_probe_port();
    }
    m.particleCount = w.particle_count();
    m.units = detail::str(w.units());
    m.publishRateHz = w.publish_rate_hz();
    m.probeReach = w.probe_reach();
    m.mapBytes = w.map_bytes();
    m.mapKey = w.map_key();
    m.sessionTimeoutS = w.session_timeout_s();
    m.unitSystem.lengthMm = w.length_mm();
    m.unitSystem.massKg = w.mass_kg();
    m.unitSystem.timeS = w.time_s();
    m.unitSystem.physical = w.physical_units();
    if (const wire::Tunables* t = w.tunables()) {
        // Copied byte-wise: the verifier checks a vector's length field, not that its doubles are
        // 8-byte aligned, and a hostile buffer may misalign them (little-endian, as on the wire).
        const auto doubles = [](const flatbuffers::Vector<double>* v) {
            std::vector<double> out(v ? v->size() : 0);
            if (!out.empty()) std::memcpy(out.data(), v->Data(), out.size() * sizeof(double));
            return out;
        };
        m.tunables = {doubles(t->lj()),
                      doubles(t->co_normal()),
                      doubles(t->co_planar()),
                      doubles(t->drag_v()),
                      doubles(t->drag_w()),
                      t->k0(),
                      t->k1()};
    }
    const Validation v = validate(m);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
