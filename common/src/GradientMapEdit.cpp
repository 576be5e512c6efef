// The windowed map edit of a cut (GradientMapEdit.hpp, docs/shape-pipeline.md "Map edits").
//
// Why the window is exact: with S the old surface voxels, R the swept ones and N the volume voxels
// next to R that become surface, the new surface is (S \ R) + N. A voxel whose old nearest surface
// voxel s survives keeps it unless a site of the window is nearer (a nearer site outside the window
// would have been nearer before too); a voxel whose s was swept takes the window's nearest, which
// is exact when no voxel outside the window can be nearer (checked: its distance is at most the
// gap to the window's open sides). Every voxel of the two layers around the window must keep its
// old answer; otherwise the window doubles its margin and the edit runs again.
#include "bop/common/GradientMapEdit.hpp"

#include "bop/common/DistanceTransform.hpp"

#include <algorithm>
#include <climits>
#include <stdexcept>

namespace bop {
namespace {

using V3i = Eigen::Vector3i;

V3i dimsOf(const Dims& d) {
    return {d.nx, d.ny, d.nz};
}
VoxelWindow grown(const VoxelWindow& w, int m, const Dims& whole) {
    return {(w.lo - V3i::Constant(m)).cwiseMax(0), (w.hi + V3i::Constant(m)).cwiseMin(dimsOf(whole))};
}
bool holdsVoxel(const VoxelWindow& w, const V3i& c) {
    return (c.array() >= w.lo.array()).all() && (c.array() < w.hi.array()).all();
}
std::size_t indexIn(const VoxelWindow& w, const V3i& c) {
    const V3i l = c - w.lo;
    return w.dims().index(l.x(), l.y(), l.z());
}
template <class F>
void forEachVoxel(const VoxelWindow& w, F&& f) {
    for (int k = w.lo.z(); k < w.hi.z(); ++k)
        for (int j = w.lo.y(); j < w.hi.y(); ++j)
            for (int i = w.lo.x(); i < w.hi.x(); ++i) f(V3i(i, j, k));
}
const SurfaceVoxel* findRecord(const std::vector<SurfaceVoxel>& recs, std::uint32_t voxel) {
    const auto it = std::lower_bound(recs.begin(), recs.end(), voxel,
                                     [](const SurfaceVoxel& s, std::uint32_t v) { return s.voxel < v; });
    return it != recs.end() && it->voxel == voxel ? &*it : nullptr;
}

constexpr std::uint8_t kRemoved = 1, kNewSurface = 2;
constexpr int kFace[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};

// The edited image over the read window X: the sweep taken out, the labels of its face
// neighbours redone (paper §3.3's rule: a voxel of bag b next to a voxel outside b is surface).
struct EditedImage {
    VoxelWindow X;
    std::vector<std::uint8_t> occ, changed;
    VoxelWindow changedBox{V3i::Constant(INT_MAX), V3i::Constant(INT_MIN)};
    std::size_t removed = 0, newSurface = 0;
    std::vector<int> bags;  // that lost voxels
};

EditedImage editImage(const GradientMap& crop, const VoxelWindow& X, const VoxelWindow& box,
                      const VoxelPredicate& takes) {
    EditedImage e;
    e.X = X;
    e.occ = crop.occ;
    e.changed.assign(e.occ.size(), 0);
    const Dims& whole = crop.wholeDims();
    auto mark = [&](const V3i& c, std::uint8_t how) {
        e.changed[indexIn(X, c)] = how;
        e.changedBox.lo = e.changedBox.lo.cwiseMin(c);
        e.changedBox.hi = e.changedBox.hi.cwiseMax(c + V3i::Ones());
    };
    std::vector<V3i> removed;
    forEachVoxel(box, [&](const V3i& c) {
        std::uint8_t& o = e.occ[indexIn(X, c)];
        if (o == 0 || !takes(c)) return;
        const int bag = bagOfSpecies(o);
        if (std::find(e.bags.begin(), e.bags.end(), bag) == e.bags.end()) e.bags.push_back(bag);
        o = 0;
        mark(c, kRemoved);
        removed.push_back(c);
    });
    e.removed = removed.size();
    auto outsideBag = [&](const V3i& c, int bag) {
        return !whole.contains(c.x(), c.y(), c.z()) || !crop.bagWithin(bagOfSpecies(e.occ[indexIn(X, c)]), bag);
    };
    for (const V3i& r : removed)
        for (const auto& f : kFace) {
            const V3i u = r + V3i(f[0], f[1], f[2]);
            if (!whole.contains(u.x(), u.y(), u.z())) continue;
            std::uint8_t& o = e.occ[indexIn(X, u)];
            if (o == 0 || isSurfaceSpecies(o)) continue;
            const int bag = bagOfSpecies(o);
            bool surface = false;
            for (const auto& g : kFace) surface = surface || outsideBag(u + V3i(g[0], g[1], g[2]), bag);
            if (!surface) continue;
            o = std::uint8_t(surfaceSpeciesOfBag(bag));
            mark(u, kNewSurface);
            ++e.newSurface;
        }
    return e;
}

// Whether each voxel of W lies within `reach` voxels (along every axis) of a changed voxel.
std::vector<std::uint8_t> nearChange(const EditedImage& e, const VoxelWindow& W, int reach) {
    const Dims d = W.dims();
    std::vector<std::uint8_t> near(d.count(), 0);
    forEachVoxel(W, [&](const V3i& c) { near[indexIn(W, c)] = e.changed[indexIn(e.X, c)] != 0; });
    // Dilation along each axis in turn by a running count over the line.
    const int n[3] = {d.nx, d.ny, d.nz};
    const std::size_t stride[3] = {1, std::size_t(d.nx), std::size_t(d.nx) * std::size_t(d.ny)};
    std::vector<int> prefix;
    for (int a = 0; a < 3; ++a) {
        const int len = n[a];
        prefix.assign(std::size_t(len) + 1, 0);
        for (std::size_t start = 0; start < d.count(); ++start) {
            if ((start / stride[a]) % std::size_t(len) != 0) continue;  // not the first voxel of a line
            for (int t = 0; t < len; ++t)
                prefix[std::size_t(t) + 1] = prefix[std::size_t(t)] + (near[start + t * stride[a]] & 1);
            for (int t = 0; t < len; ++t) {
                const int lo = std::max(t - reach, 0), hi = std::min(t + reach + 1, len);
                near[start + t * stride[a]] = std::uint8_t(
                    (near[start + t * stride[a]] & 1) | ((prefix[std::size_t(hi)] - prefix[std::size_t(lo)] > 0) << 1));
            }
            for (int t = 0; t < len; ++t) near[start + t * stride[a]] >>= 1;
        }
    }
    return near;
}

}  // namespace

bool BladeSweep::holds(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (x - (a + t * ab)).squaredNorm() <= radius * radius;
}

MapPatch cutPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels, const BladeSweep& blade,
                  const SurfaceGeometryParams& p) {
    const V3i n = dimsOf(whole);
    VoxelWindow box;  // voxels whose centres can lie in the sweep
    for (int a = 0; a < 3; ++a) {
        const double lo = std::min(blade.a[a], blade.b[a]) - blade.radius - 0.5;
        const double hi = std::max(blade.a[a], blade.b[a]) + blade.radius - 0.5;
        box.lo[a] = int(std::clamp(std::ceil(lo), 0.0, double(n[a])));
        box.hi[a] = int(std::clamp(std::floor(hi) + 1, 0.0, double(n[a])));
        if (!(box.lo[a] < box.hi[a])) return {};
    }
    return removalPatch(
        read, whole, r0Voxels, box,
        [&](const V3i& c) { return blade.holds(c.cast<double>() + Eigen::Vector3d::Constant(0.5)); }, p);
}

MapPatch removalPatch(const MapWindowReader& read, const Dims& whole, double r0Voxels, const VoxelWindow& box,
                      const VoxelPredicate& takes, const SurfaceGeometryParams& p) {
    MapPatch patch;
    const V3i n = dimsOf(whole);
    const SurfaceKernels kernels(p.sigmaVoxels);
    const int K = kernels.radius;
    std::vector<double> scratch;
    for (int margin = K + 2;; margin *= 2, ++patch.grows) {
        // Read enough around the box (the changes lie within one voxel of it) for the window, its
        // two checked layers, and the filters of the surface voxels within K + 1 of a change.
        const VoxelWindow X = grown(box, 1 + std::max(margin + 2, 2 * K + 1), whole);
        const GradientMap crop = read(X);
        const EditedImage e = editImage(crop, X, box, takes);
        if (e.removed == 0) return patch;
        const VoxelWindow W = grown(e.changedBox, margin, whole), Wext = grown(W, 2, whole);
        const bool everything = W.lo == V3i::Zero() && W.hi == n;

        // The exact distance transform of the new surface over W and its two layers.
        std::vector<std::int32_t> feature(Wext.dims().count(), kNoSite), dist2;
        std::vector<std::uint32_t> sites;
        forEachVoxel(Wext, [&](const V3i& c) {
            if (!isSurfaceSpecies(e.occ[indexIn(X, c)])) return;
            feature[indexIn(Wext, c)] = std::int32_t(sites.size());
            sites.push_back(std::uint32_t(whole.index(c.x(), c.y(), c.z())));
        });
        exactDistanceTransform(Wext.dims(), feature, dist2, 1);

        // The old records' places and whether the blade took them, once per record.
        std::vector<V3i> placeOf(crop.surface.size());
        std::vector<char> goneOf(crop.surface.size());
        for (std::size_t r = 0; r < crop.surface.size(); ++r) {
            placeOf[r] = whole.coords(crop.surface[r].voxel);
            goneOf[r] = holdsVoxel(X, placeOf[r]) && e.changed[indexIn(X, placeOf[r])] == kRemoved;
        }
        std::vector<std::uint32_t> nearest(W.dims().count());
        bool exact = true;
        forEachVoxel(Wext, [&](const V3i& c) {
            if (!exact) return;
            const std::uint32_t record = crop.nearest[indexIn(X, c)];
            const std::uint32_t old = crop.surface[record].voxel;
            const std::int64_t dOld = (c - placeOf[record]).cast<std::int64_t>().squaredNorm();
            const bool gone = goneOf[record];
            const std::size_t ei = indexIn(Wext, c);
            const std::int64_t dNew = feature[ei] == kNoSite ? INT64_MAX : dist2[ei];
            if (!holdsVoxel(W, c)) {  // the layers around the window keep their answers
                exact = !gone && dNew >= dOld;
                return;
            }
            const bool keep = !gone && dOld <= dNew;
            if (gone) {  // no voxel beyond the window's open sides may be nearer
                std::int64_t gap = INT64_MAX;
                for (int a = 0; a < 3; ++a) {
                    if (W.lo[a] > 0) gap = std::min<std::int64_t>(gap, c[a] - W.lo[a] + 1);
                    if (W.hi[a] < n[a]) gap = std::min<std::int64_t>(gap, W.hi[a] - c[a]);
                }
                exact = dNew != INT64_MAX && (gap == INT64_MAX || dNew <= gap * gap);
                if (!exact) return;  // no site here: a wider window, or none left at all
            }
            nearest[indexIn(W, c)] = keep ? old : sites[std::size_t(feature[ei])];
        });
        if (!exact && !everything) continue;
        if (!exact) throw std::domain_error("the edit would leave no bag in the map");

        // Records: recomputed within the filters' reach of a change, the old ones elsewhere. The
        // indicator of each bag met, over the read window, once.
        const std::vector<std::uint8_t> near = nearChange(e, W, K + 1);
        // Padded by K on every side, beyond the grid outside: a look-up without a bounds check.
        std::vector<std::vector<std::uint8_t>> outsideOf(std::size_t(crop.bagCount) + 1);
        const Dims xd = X.dims(), pd{xd.nx + 2 * K, xd.ny + 2 * K, xd.nz + 2 * K};
        std::vector<SurfaceVoxel> fresh;
        forEachVoxel(W, [&](const V3i& c) {
            const std::uint8_t o = e.occ[indexIn(X, c)];
            if (!isSurfaceSpecies(o) || !near[indexIn(W, c)]) return;
            const int bag = bagOfSpecies(o);
            std::vector<std::uint8_t>& chi = outsideOf.at(std::size_t(bag));
            if (chi.empty()) {
                chi.assign(pd.count(), 1);
                forEachVoxel(X, [&](const V3i& u) {
                    const V3i p = u - X.lo + V3i::Constant(K);
                    chi[pd.index(p.x(), p.y(), p.z())] = !crop.bagWithin(bagOfSpecies(e.occ[indexIn(X, u)]), bag);
                });
            }
            const std::uint8_t* base = chi.data() + pd.index(K - X.lo.x(), K - X.lo.y(), K - X.lo.z());
            const std::ptrdiff_t sy = pd.nx, sz = std::ptrdiff_t(pd.nx) * pd.ny;
            // (x, y, z) within K of a surface voxel near a change: inside the padded window
            auto outside = [&](int x, int y, int z) { return base[x + sy * y + sz * z] != 0; };
            SurfaceVoxel sv;
            sv.voxel = std::uint32_t(whole.index(c.x(), c.y(), c.z()));
            sv.species = o;
            setSurfaceGeometry(sv, indicatorDerivatives(outside, c.x(), c.y(), c.z(), kernels, scratch),
                               faceNormal(outside, c.x(), c.y(), c.z()), r0Voxels, p);
            fresh.push_back(sv);
        });
        std::vector<std::uint32_t> named;
        for (std::uint32_t id : nearest)
            if (named.empty() || named.back() != id) named.push_back(id);  // runs of one record, once
        std::sort(named.begin(), named.end());
        named.erase(std::unique(named.begin(), named.end()), named.end());
        std::vector<SurfaceVoxel> kept;
        for (std::uint32_t id : named) {
            if (findRecord(fresh, id)) continue;
            const SurfaceVoxel* r = findRecord(crop.surface, id);
            if (!r) throw std::logic_error("cutPatch: a nearest surface voxel without its record");
            kept.push_back(*r);
        }
        patch.records.resize(fresh.size() + kept.size());
        std::merge(fresh.begin(), fresh.end(), kept.begin(), kept.end(), patch.records.begin(),
                   [](const SurfaceVoxel& x, const SurfaceVoxel& y) { return x.voxel < y.voxel; });
        patch.window = W;
        patch.occ.resize(W.dims().count());
        forEachVoxel(W, [&](const V3i& c) { patch.occ[indexIn(W, c)] = e.occ[indexIn(X, c)]; });
        patch.nearest = std::move(nearest);
        patch.removed = e.removed;
        patch.newSurface = e.newSurface;
        patch.bags = e.bags;
        std::sort(patch.bags.begin(), patch.bags.end());
        return patch;
    }
}

GradientMap applyPatch(const GradientMap& map, const MapPatch& patch) {
    if (patch.empty()) return map;
    const VoxelWindow M{map.origin, map.origin + dimsOf(map.dims())};
    VoxelWindow I{M.lo.cwiseMax(patch.window.lo), M.hi.cwiseMin(patch.window.hi)};
    if ((I.lo.array() >= I.hi.array()).any()) I.hi = I.lo;  // no overlap
    // The old records still named from outside the patch's window, and the patch's named inside it.
    std::vector<std::uint8_t> used(map.surface.size(), 0);
    std::vector<std::uint32_t> fromPatch;
    forEachVoxel(M, [&](const V3i& c) {
        if (holdsVoxel(I, c)) {
            const std::uint32_t id = patch.nearest[indexIn(patch.window, c)];
            if (fromPatch.empty() || fromPatch.back() != id) fromPatch.push_back(id);  // runs once
        } else
            used[map.nearest[indexIn(M, c)]] = 1;
    });
    std::sort(fromPatch.begin(), fromPatch.end());
    fromPatch.erase(std::unique(fromPatch.begin(), fromPatch.end()), fromPatch.end());
    GradientMap out = map;  // the header and the occupancy; the records and nearest are redone
    out.surface.clear();
    std::vector<std::uint32_t> oldToNew(map.surface.size(), 0);
    auto recordOf = [&](const SurfaceVoxel& old) {
        const SurfaceVoxel* r = findRecord(patch.records, old.voxel);
        return r ? *r : old;
    };
    std::size_t i = 0, j = 0;
    while (i < map.surface.size() || j < fromPatch.size()) {
        while (i < map.surface.size() && !used[i]) ++i;
        const bool haveOld = i < map.surface.size(), havePatch = j < fromPatch.size();
        if (!haveOld && !havePatch) break;
        if (haveOld && (!havePatch || map.surface[i].voxel <= fromPatch[j])) {
            if (havePatch && map.surface[i].voxel == fromPatch[j]) ++j;
            oldToNew[i] = std::uint32_t(out.surface.size());
            out.surface.push_back(recordOf(map.surface[i++]));
        } else {
            const SurfaceVoxel* r = findRecord(patch.records, fromPatch[j++]);
            if (!r) throw std::logic_error("applyPatch: the patch names a surface voxel it has no record of");
            out.surface.push_back(*r);
        }
    }
    forEachVoxel(M, [&](const V3i& c) {
        const std::size_t v = indexIn(M, c);
        if (!holdsVoxel(I, c)) {
            out.nearest[v] = oldToNew[map.nearest[v]];
            return;
        }
        const std::size_t pv = indexIn(patch.window, c);
        out.occ[v] = patch.occ[pv];
        const std::uint32_t id = patch.nearest[pv];
        out.nearest[v] =
            std::uint32_t(std::lower_bound(out.surface.begin(), out.surface.end(), id,
                                           [](const SurfaceVoxel& s, std::uint32_t x) { return s.voxel < x; }) -
                          out.surface.begin());
    });
    return out;
}

}  // namespace bop
