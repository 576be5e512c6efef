// State frames and their chunks, float32, 16-bit quantised or compact (Quantise.hpp).
#include "codec/BufferPool.hpp"
#include "codec/Checker.hpp"
#include "codec/Codec.hpp"
#include "codec/Quantise.hpp"
#include "codec/WireSupport.hpp"
#include "frame_generated.h"

#include <algorithm>
#include <array>
#include <cstring>

// Float, uint16 and uint64 arrays are copied out of the buffer with memcpy, which assumes the
// host has FlatBuffers' byte order (little-endian).
static_assert(FLATBUFFERS_LITTLEENDIAN, "the frame codec copies little-endian arrays as they are");

namespace bop::protocol {

namespace {

// Bytes a chunk needs besides its particle arrays: identifier, vtable, header fields, the
// FrameStats table, array lengths and alignment padding (about 450 bytes; twice that kept free).
constexpr std::size_t kChunkOverheadBytes = 1024;

// Elements of an optional wire vector; 0 when absent.
template <class V>
std::size_t sizeOf(const V* v) {
    return v ? v->size() : 0;
}

// Copies a wire array into `out`, reusing its capacity (no allocation when it is large enough).
template <class T>
void copyOut(const flatbuffers::Vector<T>* v, std::vector<T>& out) {
    out.resize(sizeOf(v));
    if (!out.empty()) std::memcpy(out.data(), v->Data(), out.size() * sizeof(T));
}

// Compact8: particles [begin, end) of m grouped by species (a stable counting sort), their
// arrays gathered in that order, and the runs of species.
struct Grouped {
    std::vector<float> positions, normals;
    std::vector<std::uint64_t> ids;
    std::vector<std::uint8_t> runSpecies;
    std::vector<std::uint32_t> runLengths;
};

void groupBySpecies(const StateFrame& m, std::size_t begin, std::size_t end, Grouped& g) {
    std::array<std::uint32_t, 257> start{};
    for (std::size_t i = begin; i < end; ++i) ++start[m.species[i] + 1];
    g.runSpecies.clear();
    g.runLengths.clear();
    for (int s = 0; s < 256; ++s) {
        if (start[s + 1] > 0) g.runSpecies.push_back(std::uint8_t(s)), g.runLengths.push_back(start[s + 1]);
        start[s + 1] += start[s];
    }
    const std::size_t k = end - begin;
    const bool withNormals = !m.normals.empty(), withIds = !m.ids.empty();
    g.positions.resize(3 * k);
    g.normals.resize(withNormals ? 3 * k : 0);
    g.ids.resize(withIds ? k : 0);
    for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t at = start[m.species[i]]++;
        std::memcpy(&g.positions[3 * at], &m.positions[3 * i], 3 * sizeof(float));
        if (withNormals) std::memcpy(&g.normals[3 * at], &m.normals[3 * i], 3 * sizeof(float));
        if (withIds) g.ids[at] = m.ids[i];
    }
}

// Particles [begin, end) of m as chunk `index` of `count`, into `out` (its capacity reused).
void encodeChunk(const StateFrame& m, std::size_t begin, std::size_t end, std::uint32_t index, std::uint32_t count,
                 std::uint32_t firstIndex, Buffer& out) {
    const std::size_t k = end - begin;
    const bool compact = m.encoding == FrameEncoding::Compact8;
    const bool quantised = m.encoding == FrameEncoding::Quantised16;
    const bool withNormals = !m.normals.empty(), withIds = !m.ids.empty();
    // One builder per thread, cleared for each chunk: its memory stays (as large as the largest
    // chunk this thread encoded) instead of being taken afresh for every chunk.
    thread_local flatbuffers::FlatBufferBuilder fbb;
    fbb.Clear();
    flatbuffers::Offset<flatbuffers::Vector<float>> positions, normals;
    flatbuffers::Offset<flatbuffers::Vector<std::uint16_t>> qpositions, qnormals;
    flatbuffers::Offset<flatbuffers::Vector<std::uint64_t>> ids;
    flatbuffers::Offset<flatbuffers::Vector<std::uint8_t>> species, qnormals8, runSpecies;
    flatbuffers::Offset<flatbuffers::Vector<std::uint32_t>> runLengths;
    if (compact) {
        thread_local Grouped g;
        groupBySpecies(m, begin, end, g);
        std::uint16_t* q = nullptr;
        qpositions = fbb.CreateUninitializedVector(3 * k, &q);
        quantisePositions(g.positions.data(), k, m.quantLo, m.quantHi, q);
        if (withNormals) {
            std::uint8_t* q8 = nullptr;
            qnormals8 = fbb.CreateUninitializedVector(2 * k, &q8);
            octEncodeNormals8(g.normals.data(), k, q8);
        }
        if (withIds) ids = fbb.CreateVector(g.ids);
        runSpecies = fbb.CreateVector(g.runSpecies);
        runLengths = fbb.CreateVector(g.runLengths);
    } else if (quantised) {
        std::uint16_t* q = nullptr;
        qpositions = fbb.CreateUninitializedVector(3 * k, &q);
        quantisePositions(m.positions.data() + 3 * begin, k, m.quantLo, m.quantHi, q);
        if (withNormals) {
            qnormals = fbb.CreateUninitializedVector(2 * k, &q);
            octEncodeNormals(m.normals.data() + 3 * begin, k, q);
        }
    } else {
        positions = fbb.CreateVector(m.positions.data() + 3 * begin, 3 * k);
        if (withNormals) normals = fbb.CreateVector(m.normals.data() + 3 * begin, 3 * k);
    }
    if (!compact) {
        if (withIds) ids = fbb.CreateVector(m.ids.data() + begin, k);
        species = fbb.CreateVector(m.species.data() + begin, k);
    }
    const FrameStats& s = m.stats;
    const wire::LoopStats haptic = detail::toWire(s.haptic);
    const auto stats = wire::CreateFrameStats(fbb, s.kinetic, s.potential, s.pressure, s.stepRateHz, s.particleCount,
                                              &haptic, s.cavityVolume, s.mapFrame, s.realTimeFactor);
    const wire::Vec3 probePos = detail::toWire(m.probePosition), probeForce = detail::toWire(m.probeForce);
    const wire::Vec3 lo = detail::toWire(m.quantLo), hi = detail::toWire(m.quantHi);

    wire::StateFrameBuilder b(fbb);
    b.add_frame_seq(m.frameSeq);
    b.add_chunk_index(index);
    b.add_chunk_count(count);
    b.add_step(m.step);
    b.add_sim_time(m.simTime);
    b.add_server_time_ns(m.serverTimeNs);
    b.add_probe_position(&probePos);
    b.add_probe_force(&probeForce);
    b.add_probe_active(m.probeActive);
    b.add_stats(stats);
    b.add_frame_particle_count(m.frameParticleCount);
    b.add_first_index(firstIndex);
    if (!compact) b.add_species(species);
    if (withIds) b.add_ids(ids);
    b.add_encoding(wire::FrameEncoding(m.encoding));
    if (compact) {
        b.add_quant_lo(&lo);
        b.add_quant_hi(&hi);
        b.add_qpositions(qpositions);
        if (withNormals) b.add_qnormals8(qnormals8);
        b.add_run_species(runSpecies);
        b.add_run_lengths(runLengths);
    } else if (quantised) {
        b.add_quant_lo(&lo);
        b.add_quant_hi(&hi);
        b.add_qpositions(qpositions);
        if (withNormals) b.add_qnormals(qnormals);
    } else {
        b.add_positions(positions);
        if (withNormals) b.add_normals(normals);
    }
    wire::FinishStateFrameBuffer(fbb, b.Finish());
    out.assign(fbb.GetBufferPointer(), fbb.GetBufferPointer() + fbb.GetSize());
}

// Array lengths of a verified chunk against its particle count (the arrays of the encoding not
// in use must be empty), and the quantisation bounds, which must be sane before dequantising.
// A Compact8 chunk's particle count: the sum of its run lengths (at most 2^28 runs of at most
// 2^32 - 1: no overflow in 64 bits).
std::uint64_t compactCount(const wire::StateFrame& w) {
    std::uint64_t n = 0;
    if (w.run_lengths())
        for (const std::uint32_t r : *w.run_lengths()) n += r;
    return n;
}

// Compact8 runs as the encoder writes them: species strictly increasing, no empty run. Any other
// order would come back regrouped from a decode and encode, a different value.
bool runsAscending(const wire::StateFrame& w) {
    if (!w.run_species() || !w.run_lengths() || w.run_species()->size() != w.run_lengths()->size()) return true;
    for (flatbuffers::uoffset_t r = 0; r < w.run_species()->size(); ++r)
        if (w.run_lengths()->Get(r) == 0 || (r > 0 && w.run_species()->Get(r) <= w.run_species()->Get(r - 1)))
            return false;
    return true;
}

Validation checkWireLengths(const wire::StateFrame& w) {
    detail::Checker c("StateFrame");
    const bool compact = w.encoding() == wire::FrameEncoding::Compact8;
    const std::uint64_t n = compact ? compactCount(w) : sizeOf(w.species());
    const auto got = [](std::size_t size) { return std::to_string(size) + " values"; };
    const bool noPlainArrays =
        sizeOf(w.qnormals8()) == 0 && sizeOf(w.run_species()) == 0 && sizeOf(w.run_lengths()) == 0;
    if (compact) {
        c.require(sizeOf(w.run_species()) == sizeOf(w.run_lengths()), DecodeError::BadLength, "run_species",
                  got(sizeOf(w.run_species())) + ", expected one per run (" + got(sizeOf(w.run_lengths())) + ")") &&
            c.require(
                runsAscending(w), DecodeError::OutOfRange, "run_species",
                "runs must be of increasing species, each at least 1 particle long (as the encoder groups them)") &&
            c.require(sizeOf(w.qpositions()) == 3 * n, DecodeError::BadLength, "qpositions",
                      got(sizeOf(w.qpositions())) + ", expected 3 x " + std::to_string(n) + " (the runs' particles)") &&
            c.require(sizeOf(w.qnormals8()) == 0 || sizeOf(w.qnormals8()) == 2 * n, DecodeError::BadLength, "qnormals8",
                      got(sizeOf(w.qnormals8())) + ", expected 0 or 2 x " + std::to_string(n)) &&
            c.require(sizeOf(w.positions()) == 0 && sizeOf(w.normals()) == 0 && sizeOf(w.qnormals()) == 0 &&
                          sizeOf(w.species()) == 0,
                      DecodeError::BadLength, "positions/normals/qnormals/species",
                      "arrays of another encoding in a Compact8 chunk") &&
            c.require(w.quant_lo() && w.quant_hi(), DecodeError::MissingField, "quant_lo/quant_hi", "absent") &&
            detail::checkQuantBounds(c, detail::toEigen(*w.quant_lo()), detail::toEigen(*w.quant_hi()));
        return c.result();
    }
    if (!noPlainArrays) {
        c.fail(DecodeError::BadLength, "qnormals8/run_species/run_lengths",
               "Compact8 arrays in a chunk of another encoding");
        return c.result();
    }
    if (w.encoding() == wire::FrameEncoding::Quantised16) {
        c.require(sizeOf(w.qpositions()) == 3 * n, DecodeError::BadLength, "qpositions",
                  got(sizeOf(w.qpositions())) + ", expected 3 x " + std::to_string(n)) &&
            c.require(sizeOf(w.qnormals()) == 0 || sizeOf(w.qnormals()) == 2 * n, DecodeError::BadLength, "qnormals",
                      got(sizeOf(w.qnormals())) + ", expected 0 or 2 x " + std::to_string(n)) &&
            c.require(sizeOf(w.positions()) == 0 && sizeOf(w.normals()) == 0, DecodeError::BadLength,
                      "positions/normals", "float arrays in a quantised chunk") &&
            c.require(w.quant_lo() && w.quant_hi(), DecodeError::MissingField, "quant_lo/quant_hi", "absent") &&
            detail::checkQuantBounds(c, detail::toEigen(*w.quant_lo()), detail::toEigen(*w.quant_hi()));
    } else if (w.encoding() == wire::FrameEncoding::Float32) {
        c.require(sizeOf(w.qpositions()) == 0 && sizeOf(w.qnormals()) == 0, DecodeError::BadLength,
                  "qpositions/qnormals", "quantised arrays in a float32 chunk");
    } else {
        c.fail(DecodeError::Unsupported, "encoding", "unknown encoding " + std::to_string(int(w.encoding())));
    }
    // Float lengths and ids are checked on the plain struct by validate().
    return c.result();
}

}  // namespace

Buffer encodeStateFrame(const StateFrame& m) {
    detail::requireValid(validate(m));
    Buffer out;
    encodeChunk(m, 0, m.count(), m.chunkIndex, m.chunkCount, m.firstIndex, out);
    return out;
}

std::vector<Buffer> encodeStateFrameChunks(const StateFrame& m, std::size_t maxChunkBytes, BufferPool* pool) {
    if (m.chunkIndex != 0 || m.chunkCount != 1 || m.firstIndex != 0 || m.frameParticleCount != m.count())
        throw EncodeError(
            "cannot encode StateFrame chunks: the frame must be whole (chunk 0 of 1, first index 0, "
            "frame_particle_count = its particle count)");
    detail::requireValid(validate(m));
    const std::size_t bpp = bytesPerParticle(m.encoding, !m.normals.empty(), !m.ids.empty());
    maxChunkBytes = std::min(maxChunkBytes, kAbsoluteMaxBytes);
    if (maxChunkBytes < kChunkOverheadBytes + bpp)
        throw EncodeError("cannot encode StateFrame chunks of at most " + std::to_string(maxChunkBytes) +
                          " bytes: a chunk needs " + std::to_string(kChunkOverheadBytes + bpp));
    const std::size_t perChunk = (maxChunkBytes - kChunkOverheadBytes) / bpp;
    const std::size_t n = m.count();
    const std::size_t chunks = std::max<std::size_t>(1, (n + perChunk - 1) / perChunk);
    if (chunks > FrameLimits{}.maxChunkCount)
        throw EncodeError("cannot encode StateFrame in " + std::to_string(chunks) + " chunks: receivers accept " +
                          std::to_string(FrameLimits{}.maxChunkCount) + " by default");
    std::vector<Buffer> out;
    out.reserve(chunks);
    for (std::size_t c = 0; c < chunks; ++c) {
        const std::size_t begin = c * perChunk, end = std::min(n, begin + perChunk);
        out.push_back(pool ? pool->take() : Buffer{});
        encodeChunk(m, begin, end, std::uint32_t(c), std::uint32_t(chunks), std::uint32_t(begin), out.back());
    }
    return out;
}

Validation decodeStateFrameInto(const std::uint8_t* buf, std::size_t len, StateFrame& m, const FrameLimits& limits) {
    // One root table and FrameStats; the cap is the receiver's (FrameLimits).
    const detail::MessageSpec spec{"StateFrame",
                                   wire::StateFrameIdentifier(),
                                   std::min(limits.maxChunkBytes, kAbsoluteMaxBytes),
                                   4,
                                   4,
                                   &wire::VerifyStateFrameBuffer};
    const detail::VerifiedBuffer vb(buf, len, spec);
    if (!vb.ok()) return {vb.error(), vb.message()};
    const wire::StateFrame& w = *wire::GetStateFrame(vb.data());
    if (const Validation lengths = checkWireLengths(w); !lengths.ok()) return lengths;

    m.frameSeq = w.frame_seq();
    m.chunkIndex = w.chunk_index();
    m.chunkCount = w.chunk_count();
    m.step = w.step();
    m.simTime = w.sim_time();
    m.serverTimeNs = w.server_time_ns();
    m.probePosition = w.probe_position() ? detail::toEigen(*w.probe_position()) : Eigen::Vector3d::Zero();
    m.probeForce = w.probe_force() ? detail::toEigen(*w.probe_force()) : Eigen::Vector3d::Zero();
    m.probeActive = w.probe_active();
    m.stats = {};
    if (const wire::FrameStats* s = w.stats())
        m.stats = {
            s->kinetic_energy(), s->potential_energy(), s->pressure(),
            s->step_rate_hz(),   s->particle_count(),   s->haptic() ? detail::toLoopStats(*s->haptic()) : LoopStats{},
            s->cavity_volume(),  s->map_frame(),        s->real_time_factor()};
    m.frameParticleCount = w.frame_particle_count();
    m.firstIndex = w.first_index();
    m.encoding = FrameEncoding(w.encoding());
    if (m.encoding == FrameEncoding::Compact8) {
        m.species.clear();  // runs expanded; checkWireLengths bounded their sum by qpositions
        m.species.reserve(compactCount(w));
        for (flatbuffers::uoffset_t r = 0; r < sizeOf(w.run_lengths()); ++r)
            m.species.insert(m.species.end(), w.run_lengths()->Get(r), w.run_species()->Get(r));
    } else {
        copyOut(w.species(), m.species);
    }
    copyOut(w.ids(), m.ids);
    const std::size_t n = m.species.size();
    if (m.encoding == FrameEncoding::Compact8) {
        const auto* qpositions =
            w.qpositions() ? reinterpret_cast<const std::uint16_t*>(w.qpositions()->Data()) : nullptr;
        m.quantLo = detail::toEigen(*w.quant_lo());
        m.quantHi = detail::toEigen(*w.quant_hi());
        m.positions.resize(3 * n);
        dequantisePositions(qpositions, n, m.quantLo, m.quantHi, m.positions.data());
        const std::size_t normals = sizeOf(w.qnormals8()) / 2;
        m.normals.resize(3 * normals);
        if (normals > 0) octDecodeNormals8(w.qnormals8()->Data(), n, m.normals.data());
    } else if (m.encoding == FrameEncoding::Quantised16) {
        // Decoded straight from the verified buffer: aligned (VerifiedBuffer), its arrays read the
        // way FlatBuffers' own accessors read them.
        // An empty chunk may leave qpositions out altogether (0 values: checkWireLengths passed it).
        const auto* qpositions =
            w.qpositions() ? reinterpret_cast<const std::uint16_t*>(w.qpositions()->Data()) : nullptr;
        const auto* qnormals = w.qnormals() ? reinterpret_cast<const std::uint16_t*>(w.qnormals()->Data()) : nullptr;
        m.quantLo = detail::toEigen(*w.quant_lo());
        m.quantHi = detail::toEigen(*w.quant_hi());
        m.positions.resize(3 * n);
        dequantisePositions(qpositions, n, m.quantLo, m.quantHi, m.positions.data());
        const std::size_t normals = sizeOf(w.qnormals()) / 2;
        m.normals.resize(3 * normals);
        if (normals > 0) octDecodeNormals(qnormals, n, m.normals.data());
    } else {
        m.quantLo = Eigen::Vector3d::Zero();
        m.quantHi = Eigen::Vector3d::Ones();
        copyOut(w.positions(), m.positions);
        copyOut(w.normals(), m.normals);
    }
    return validate(m, limits);
}

Decoded<StateFrame> decodeStateFrame(const std::uint8_t* buf, std::size_t len, const FrameLimits& limits) {
    StateFrame m;
    const Validation v = decodeStateFrameInto(buf, len, m, limits);
    return detail::accept(std::move(m), v);
}

}  // namespace bop::protocol
