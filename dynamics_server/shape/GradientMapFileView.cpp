#include "GradientMapFileView.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/GradientMapFileFormat.hpp"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace bop::shape {
using namespace gmfile;
namespace {

// Positioned reads from the cache file. Unbuffered, so that the bytes counted are the bytes
// asked of the OS: a buffered stream would refill a whole buffer after every seek.
class File {
public:
    explicit File(const std::string& path) : path_(path) {
        in_.rdbuf()->pubsetbuf(nullptr, 0);
        in_.open(path, std::ios::binary);
        if (!in_) throw Error(path, "cannot open the gradient-map file");
        in_.seekg(0, std::ios::end);
        size_ = std::uint64_t(in_.tellg());
    }
    std::uint64_t size() const { return size_; }
    std::uint64_t bytesRead() const { return read_; }
    void read(std::uint64_t at, void* dst, std::size_t n) {
        if (at > size_ || size_ - at < n)
            throw Error(path_, "truncated gradient-map file (needs " + std::to_string(at + n) + " bytes, has " +
                                   std::to_string(size_) + "); rebuild it with bop-shape");
        in_.seekg(std::streamoff(at));
        in_.read(static_cast<char*>(dst), std::streamsize(n));
        if (std::size_t(in_.gcount()) != n) throw Error(path_, "cannot read the gradient-map file");
        read_ += n;
    }
    template <class T>
    T get(std::uint64_t at) {
        T v;
        read(at, &v, sizeof v);
        return v;
    }

private:
    const std::string& path_;
    std::ifstream in_;
    std::uint64_t size_ = 0, read_ = 0;
};

template <class T>
T load(const unsigned char* p, std::size_t& at) {
    T v;
    std::memcpy(&v, p + at, sizeof v);
    at += sizeof v;
    return v;
}

// Surface records named by one window whose indices differ by at most this many are read in
// one run: a few unused 36-byte records cost less than another seek and read.
constexpr std::uint32_t kMaxGap = 16;
constexpr std::uint32_t kUnnamed = ~std::uint32_t(0);      // a surface record the window does not name
constexpr std::size_t kChunkBytes = std::size_t(1) << 20;  // checksum streaming buffer

}  // namespace

std::optional<GradientMapFileView> GradientMapFileView::open(const std::string& path, std::uint64_t key) {
    if (!std::filesystem::exists(path)) return std::nullopt;
    File f(path);
    char magic[8] = {};
    if (f.size() >= 8) f.read(0, magic, 8);
    if (std::memcmp(magic, kMagic, 8) != 0) throw Error(path, "not a BoP gradient-map file (bad magic)");
    if (const auto v = f.get<std::uint32_t>(8); v < kVersion)
        return std::nullopt;  // made by an earlier BoP: stale
    else if (v != kVersion)
        throw Error(path, "gradient-map file version " + std::to_string(v) + ", expected " + std::to_string(kVersion));
    if (f.get<std::uint64_t>(12) != key) return std::nullopt;

    // The checksum covers every byte before it; hash the file a chunk at a time.
    std::vector<unsigned char> chunk(kChunkBytes);
    std::uint64_t h = kHashSeed;
    for (std::uint64_t at = 0, end = f.size() - 8; at < end; at += chunk.size()) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(chunk.size(), end - at));
        f.read(at, chunk.data(), n);
        h = hashBytes(chunk.data(), n, h);
    }
    if (f.get<std::uint64_t>(f.size() - 8) != h)
        throw Error(path, "gradient-map file is corrupt (checksum mismatch); rebuild it with bop-shape");

    GradientMapFileView view;
    view.path_ = path;
    view.key_ = key;
    view.size_ = f.size();
    const auto frames = f.get<std::uint32_t>(20);
    if (frames == 0 || frames > kMaxFrames) throw Error(path, "implausible frame count " + std::to_string(frames));
    std::uint64_t pos = kFileHeaderBytes;
    for (std::uint32_t i = 0; i < frames; ++i) {
        unsigned char raw[kFrameHeaderBytes];
        f.read(pos, raw, sizeof raw);
        std::size_t at = 0;
        Frame fr;
        GradientMap& m = fr.header;
        const Dims d{load<std::int32_t>(raw, at), load<std::int32_t>(raw, at), load<std::int32_t>(raw, at)};
        if (d.nx < 1 || d.ny < 1 || d.nz < 1 || d.count() >= kMaxVoxels) throw Error(path, "implausible grid size");
        m.grid.dims = d;
        for (int a = 0; a < 3; ++a) m.grid.originMm[a] = load<double>(raw, at);
        m.grid.voxelMm = load<double>(raw, at);
        m.r0Voxels = load<double>(raw, at);
        m.bagCount = load<std::int32_t>(raw, at);
        if (m.bagCount < 1 || m.bagCount > kMaxBags) throw Error(path, "implausible bag count");
        std::uint8_t parents[kParentBytes];
        std::memcpy(parents, raw + at, kParentBytes);
        at += kParentBytes;
        try {
            fromParents(parents, m);
        } catch (const std::invalid_argument& e) {
            throw Error(path, e.what());
        }
        fr.surfaceCount = load<std::uint64_t>(raw, at);
        if (fr.surfaceCount == 0 || fr.surfaceCount > d.count()) throw Error(path, "implausible surface voxel count");
        fr.occAt = pos + kFrameHeaderBytes;
        fr.nearestAt = fr.occAt + d.count();                              // u8 occ[N]
        fr.surfaceAt = fr.nearestAt + d.count() * sizeof(std::uint32_t);  // u32 nearest[N]
        pos = fr.surfaceAt + fr.surfaceCount * sizeof(SurfaceRecord);
        view.frames_.push_back(std::move(fr));
    }
    if (pos + 8 > f.size())
        throw Error(path, "truncated gradient-map file (needs " + std::to_string(pos + 8) + " bytes, has " +
                              std::to_string(f.size()) + "); rebuild it with bop-shape");
    if (pos + 8 != f.size()) throw Error(path, "trailing bytes after the last frame");
    return view;
}

const GradientMapFileView::Frame& GradientMapFileView::frame(int f) const {
    if (f < 0 || f >= frames())
        throw std::out_of_range("GradientMapFileView: no frame " + std::to_string(f) + " in " + path_);
    return frames_[std::size_t(f)];
}

GradientMap GradientMapFileView::header(int f) const {
    return frame(f).header;
}

// Bytes read per crop: 20 (identity check) + 5 per window voxel (u8 occ + u32 nearest, one read
// per contiguous run: an x row, or whole slabs when the window spans the map in x and y) + 36
// per surface record the window names (plus fewer than kMaxGap unused records between two named
// ones read in one run). The file holds 5 bytes per voxel and 36 per surface voxel, so a crop
// reads about the window's share of it.
GradientMap GradientMapFileView::crop(int f, const VoxelWindow& w, std::uint64_t* bytesRead) const {
    const Frame& fr = frame(f);
    const Dims& d = fr.header.dims();
    const Dims cd = w.dims();
    if ((w.lo.array() < 0).any() || w.hi.x() > d.nx || w.hi.y() > d.ny || w.hi.z() > d.nz || cd.nx < 1 || cd.ny < 1 ||
        cd.nz < 1)
        throw std::invalid_argument("GradientMapFileView::crop: window outside the map or empty");
    File file(path_);
    if (file.size() != size_ || file.get<std::uint64_t>(12) != key_)
        throw Error(path_, "the gradient-map file changed since it was opened; open it again");

    GradientMap out = fr.header;
    out.grid.dims = cd;
    out.origin = w.lo;
    out.whole = d;
    out.occ.resize(cd.count());
    out.nearest.resize(cd.count());
    // Read runs of voxels contiguous in both the window and the file: an x row; the window's
    // part of an xy plane if it spans the map in x; all of it if it spans the map in x and y.
    std::size_t run = std::size_t(cd.nx);
    if (cd.nx == d.nx) run *= std::size_t(cd.ny);
    if (cd.nx == d.nx && cd.ny == d.ny) run *= std::size_t(cd.nz);
    for (std::size_t c = 0; c < cd.count(); c += run) {
        const Eigen::Vector3i at = cd.coords(c) + w.lo;
        const std::uint64_t src = d.index(at.x(), at.y(), at.z());
        file.read(fr.occAt + src, out.occ.data() + c, run);
        file.read(fr.nearestAt + src * sizeof(std::uint32_t), out.nearest.data() + c, run * sizeof(std::uint32_t));
    }

    // The surface records the window names, in whole-map order, as cropGradientMap keeps them:
    // marked per record, then listed (linear in the voxels; a sort of every voxel's index took
    // about a second on a 12.8-million-voxel map).
    std::vector<std::uint32_t> renamed(fr.surfaceCount, kUnnamed);
    for (std::uint32_t n : out.nearest) {
        if (n >= fr.surfaceCount) throw Error(path_, "nearest-surface index out of range");
        renamed[n] = 0;
    }
    std::vector<std::uint32_t> named;
    for (std::uint64_t n = 0; n < fr.surfaceCount; ++n)
        if (renamed[n] != kUnnamed) renamed[n] = std::uint32_t(named.size()), named.push_back(std::uint32_t(n));
    out.surface.reserve(named.size());
    std::vector<SurfaceRecord> recs;
    for (std::size_t a = 0, b = 0; a < named.size(); a = b) {
        for (b = a + 1; b < named.size() && named[b] - named[b - 1] <= kMaxGap;) ++b;
        recs.resize(named[b - 1] - named[a] + 1);  // records named[a] .. named[b-1], one read
        file.read(fr.surfaceAt + std::uint64_t(named[a]) * sizeof(SurfaceRecord), recs.data(),
                  recs.size() * sizeof(SurfaceRecord));
        for (std::size_t s = a; s < b; ++s) {
            const SurfaceRecord& x = recs[named[s] - named[a]];
            // A surface species is odd, so nonzero; its voxel's occ is at hand only inside the window.
            bool ok = x.voxel < d.count() && isSurfaceSpecies(x.species);
            if (const Eigen::Vector3i c = d.coords(x.voxel) - w.lo; ok && cd.contains(c.x(), c.y(), c.z()))
                ok = out.occ[cd.index(c.x(), c.y(), c.z())] == x.species;
            if (!ok) throw Error(path_, "inconsistent surface record");
            out.surface.push_back({x.voxel,
                                   x.species,
                                   {x.normal[0], x.normal[1], x.normal[2]},
                                   x.meanCurvature,
                                   x.gaussCurvature,
                                   x.kappa,
                                   x.cpWeight});
        }
    }
    for (auto& n : out.nearest) n = renamed[n];
    if (bytesRead) *bytesRead = file.bytesRead();
    return out;
}

}  // namespace bop::shape
