#include "bop/common/GradientMapFile.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/GradientMapFileFormat.hpp"
#include "bop/common/Npy.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

namespace bop {
using namespace gmfile;
namespace {

struct Writer {
    std::vector<unsigned char> buf;
    void putBytes(const void* p, std::size_t n) {
        const std::size_t at = buf.size();
        buf.resize(at + n);
        if (n) std::memcpy(buf.data() + at, p, n);
    }
    template <class T>
    void put(const T& v) {
        putBytes(&v, sizeof(T));
    }
    template <class T>
    void putArray(const std::vector<T>& v) {
        putBytes(v.data(), v.size() * sizeof(T));
    }
};

struct Reader {
    std::span<const std::uint8_t> buf;
    std::size_t pos = 0;
    const std::string& path;
    void need(std::size_t n) const {
        if (buf.size() - pos < n)
            throw Error(path, "truncated gradient-map file (needs " + std::to_string(pos + n) + " bytes, has " +
                                  std::to_string(buf.size()) + "); rebuild it with bop-shape");
    }
    template <class T>
    T get() {
        need(sizeof(T));
        T v;
        std::memcpy(&v, buf.data() + pos, sizeof(T));
        pos += sizeof(T);
        return v;
    }
    template <class T>
    void getArray(std::vector<T>& v, std::size_t n) {
        need(n * sizeof(T));
        v.resize(n);
        std::memcpy(v.data(), buf.data() + pos, n * sizeof(T));
        pos += n * sizeof(T);
    }
};

}  // namespace

std::uint64_t hashText(const std::string& text) {
    return hashBytes(reinterpret_cast<const unsigned char*>(text.data()), text.size());
}

void writeGradientMaps(const std::string& path, const std::vector<GradientMap>& frames, std::uint64_t key) {
    Writer w;
    w.putBytes(kMagic, 8);
    w.put(kVersion);
    w.put(key);
    w.put(std::uint32_t(frames.size()));
    for (const GradientMap& m : frames) {
        const Dims& d = m.dims();
        w.put(std::int32_t(d.nx));
        w.put(std::int32_t(d.ny));
        w.put(std::int32_t(d.nz));
        for (int a = 0; a < 3; ++a) w.put(m.grid.originMm[a]);
        w.put(m.grid.voxelMm);
        w.put(m.r0Voxels);
        w.put(std::int32_t(m.bagCount));
        std::uint8_t parents[kParentBytes];
        toParents(m, parents);
        w.putBytes(reinterpret_cast<const char*>(parents), kParentBytes);
        w.put(std::uint64_t(m.surface.size()));
        w.putArray(m.occ);
        w.putArray(m.nearest);
        std::vector<SurfaceRecord> recs(m.surface.size());
        for (std::size_t s = 0; s < recs.size(); ++s) {
            const SurfaceVoxel& sv = m.surface[s];
            recs[s] = {sv.voxel,         sv.species,        {0, 0, 0}, {sv.normal.x(), sv.normal.y(), sv.normal.z()},
                       sv.meanCurvature, sv.gaussCurvature, sv.kappa,  sv.cpWeight};
        }
        w.putArray(recs);
    }
    w.put(hashBytes(w.buf.data(), w.buf.size()));
    writeFileAtomic(path, w.buf.data(), w.buf.size());
}

std::optional<std::vector<GradientMap>> readGradientMaps(const std::string& path, std::uint64_t key) {
    if (!std::filesystem::exists(path)) return std::nullopt;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, "cannot open the gradient-map file");
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return readGradientMaps(bytes, key, path);
}

std::optional<std::vector<GradientMap>> readGradientMaps(std::span<const std::uint8_t> buf, std::uint64_t key,
                                                         const std::string& path) {
    Reader r{buf, 0, path};
    if (buf.size() < 8 || std::memcmp(buf.data(), kMagic, 8) != 0)
        throw Error(path, "not a BoP gradient-map file (bad magic)");
    r.pos = 8;
    if (const auto v = r.get<std::uint32_t>(); v < kVersion)
        return std::nullopt;  // made by an earlier BoP: stale
    else if (v != kVersion)
        throw Error(path, "gradient-map file version " + std::to_string(v) + ", expected " + std::to_string(kVersion));
    if (r.get<std::uint64_t>() != key) return std::nullopt;
    if (buf.size() < 8 + 8) throw Error(path, "truncated gradient-map file");
    std::uint64_t stored;
    std::memcpy(&stored, buf.data() + buf.size() - 8, 8);
    if (stored != hashBytes(buf.data(), buf.size() - 8))
        throw Error(path, "gradient-map file is corrupt (checksum mismatch); rebuild it with bop-shape");
    const auto frames = r.get<std::uint32_t>();
    if (frames == 0 || frames > kMaxFrames) throw Error(path, "implausible frame count " + std::to_string(frames));
    std::vector<GradientMap> out(frames);
    for (GradientMap& m : out) {
        Dims d{r.get<std::int32_t>(), r.get<std::int32_t>(), r.get<std::int32_t>()};
        if (d.nx < 1 || d.ny < 1 || d.nz < 1 || d.count() >= kMaxVoxels) throw Error(path, "implausible grid size");
        m.grid.dims = d;
        for (int a = 0; a < 3; ++a) m.grid.originMm[a] = r.get<double>();
        m.grid.voxelMm = r.get<double>();
        m.r0Voxels = r.get<double>();
        m.bagCount = r.get<std::int32_t>();
        if (m.bagCount < 1 || m.bagCount > kMaxBags) throw Error(path, "implausible bag count");
        std::uint8_t parents[kParentBytes];
        for (auto& b : parents) b = r.get<std::uint8_t>();
        try {
            fromParents(parents, m);
        } catch (const std::invalid_argument& e) {
            throw Error(path, e.what());
        }
        const auto ns = r.get<std::uint64_t>();
        if (ns == 0 || ns > d.count()) throw Error(path, "implausible surface voxel count");
        r.getArray(m.occ, d.count());
        r.getArray(m.nearest, d.count());
        std::vector<SurfaceRecord> recs;
        r.getArray(recs, ns);
        m.surface.resize(ns);
        for (std::size_t s = 0; s < ns; ++s) {
            const SurfaceRecord& x = recs[s];
            if (x.voxel >= d.count() || m.occ[x.voxel] != x.species) throw Error(path, "inconsistent surface record");
            m.surface[s] = {x.voxel,         x.species,        {x.normal[0], x.normal[1], x.normal[2]},
                            x.meanCurvature, x.gaussCurvature, x.kappa,
                            x.cpWeight};
        }
        for (auto n : m.nearest)
            if (n >= ns) throw Error(path, "nearest-surface index out of range");
    }
    if (r.pos + 8 != buf.size()) throw Error(path, "trailing bytes after the last frame");
    return out;
}

namespace gmfile {

void toParents(const GradientMap& m, std::uint8_t (&out)[kParentBytes]) {
    std::fill(std::begin(out), std::end(out), std::uint8_t(0));
    for (int b = 1; b <= m.bagCount && b < int(kParentBytes); ++b) out[b] = std::uint8_t(m.parentBag(b));
}

void fromParents(const std::uint8_t (&in)[kParentBytes], GradientMap& m) {
    m.bagParent.assign(in, in + std::min<std::size_t>(std::size_t(m.bagCount) + 1, kParentBytes));
    m.bagParent[0] = 0;
    for (int b = 1; b <= m.bagCount; ++b) {
        int a = b;
        for (int steps = 0; a != 0; ++steps, a = m.bagParent[std::size_t(a)])
            if (a > m.bagCount || steps > m.bagCount)
                throw std::invalid_argument("bag " + std::to_string(b) + " has a parent that is no bag, or a cycle");
    }
}

}  // namespace gmfile
}  // namespace bop
