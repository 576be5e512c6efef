#include "BoundarySmoothing.hpp"

#include "SimplePoint.hpp"
#include "bop/common/DistanceTransform.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>

namespace bop::shape {
namespace {

// A box of grid voxels, [lo, hi) on each axis.
struct Box {
    Eigen::Vector3i lo, hi;
    Dims dims() const { return {hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()}; }
    std::size_t gridIndex(const Dims& grid, std::size_t local) const {
        const Eigen::Vector3i c = lo + dims().coords(local);
        return grid.index(c.x(), c.y(), c.z());
    }
};

// The mask's voxels' box grown by `pad` on each side, within the grid; empty (lo = hi) if none.
Box boxAround(const Mask& m, int pad) {
    const Dims& d = m.dims;
    Eigen::Vector3i lo(d.nx, d.ny, d.nz), hi(0, 0, 0);
    for (std::size_t v = 0; v < d.count(); ++v)
        if (m.data[v]) {
            const Eigen::Vector3i c = d.coords(v);
            lo = lo.cwiseMin(c);
            hi = hi.cwiseMax(c + Eigen::Vector3i::Ones());
        }
    if ((hi.array() <= lo.array()).any()) return {lo, lo};
    const Eigen::Vector3i top(d.nx, d.ny, d.nz);
    return {(lo.array() - pad).max(0).matrix(), (hi.array() + pad).min(top.array()).matrix()};
}

// Signed distance to the mask's boundary at each voxel of the box, voxels: inside, the distance
// to the nearest outside voxel centre less ½; outside, minus the distance to the nearest inside one less ½.
std::vector<float> signedDistance(const Mask& m, const Box& box, int threads) {
    const Dims d = box.dims();
    std::vector<std::uint8_t> in(d.count());
    for (std::size_t v = 0; v < d.count(); ++v) in[v] = m.data[box.gridIndex(m.dims, v)] != 0;
    std::vector<float> phi(d.count());
    std::vector<std::int32_t> sites(d.count()), dist2;
    for (const bool inside : {true, false}) {  // inside voxels measure to the outside ones, and back
        for (std::size_t v = 0; v < d.count(); ++v) sites[v] = bool(in[v]) == inside ? kNoSite : 0;
        exactDistanceTransform(d, sites, dist2, threads);
        for (std::size_t v = 0; v < d.count(); ++v) {
            if (bool(in[v]) != inside) continue;
            // no site in the box: the grid holds nothing but this side; as far as the box reaches
            const double r = dist2[v] == INT32_MAX ? double(d.nx + d.ny + d.nz) : std::sqrt(double(dist2[v]));
            phi[v] = float(inside ? r - 0.5 : 0.5 - r);
        }
    }
    return phi;
}

// Separable Gaussian of width sigma (voxels), cut at 3 sigma, the box's edge values held beyond it.
void gaussianSmooth(std::vector<float>& f, const Dims& d, double sigma) {
    const int r = int(std::ceil(3.0 * sigma));
    std::vector<double> w(std::size_t(2 * r + 1));
    double sum = 0;
    for (int k = -r; k <= r; ++k) sum += w[std::size_t(k + r)] = std::exp(-0.5 * k * k / (sigma * sigma));
    for (double& x : w) x /= sum;
    const int n[3] = {d.nx, d.ny, d.nz};
    const std::size_t stride[3] = {1, std::size_t(d.nx), std::size_t(d.nx) * std::size_t(d.ny)};
    std::vector<float> line;
    for (int axis = 0; axis < 3; ++axis) {
        const int len = n[axis];
        line.resize(std::size_t(len));
        for (std::size_t start = 0; start < d.count(); ++start) {
            if (d.coords(start)[axis] != 0) continue;  // one line per voxel on the axis' first plane
            for (int i = 0; i < len; ++i) line[std::size_t(i)] = f[start + std::size_t(i) * stride[axis]];
            for (int i = 0; i < len; ++i) {
                double s = 0;
                for (int k = -r; k <= r; ++k)
                    s += w[std::size_t(k + r)] * line[std::size_t(std::clamp(i + k, 0, len - 1))];
                f[start + std::size_t(i) * stride[axis]] = float(s);
            }
        }
    }
}

struct Candidate {
    std::size_t voxel;  // grid index
    float level;        // smoothed signed distance at its centre, voxels
    bool inside;        // on the bag's side before smoothing
};

// Voxel changes the candidates call for under level offset c: added minus removed.
long long netChange(const std::vector<Candidate>& cand, double c) {
    long long net = 0;
    for (const Candidate& k : cand) {
        if (k.inside && k.level + c < -kSmoothingMargin) --net;
        if (!k.inside && k.level + c > kSmoothingMargin) ++net;
    }
    return net;
}

// The offset in [-kMaxLevelShift, kMaxLevelShift] whose net change is closest to zero.
double volumeKeepingShift(const std::vector<Candidate>& cand) {
    double lo = -kMaxLevelShift, hi = kMaxLevelShift;  // netChange grows with c
    if (netChange(cand, lo) >= 0) return lo;
    if (netChange(cand, hi) <= 0) return hi;
    for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (netChange(cand, mid) < 0 ? lo : hi) = mid;
    }
    return std::llabs(netChange(cand, lo)) <= std::llabs(netChange(cand, hi)) ? lo : hi;
}

// The voxels beside the boundary (a face neighbour on the other side) that the boundary
// smoothed with width sigma and some level offset would move, and the offset that keeps the volume.
std::vector<Candidate> planChanges(const Mask& m, const Box& box, const std::vector<float>& unsmoothed, double sigma,
                                   double& shift) {
    std::vector<float> level = unsmoothed;
    gaussianSmooth(level, box.dims(), sigma);
    std::vector<Candidate> cand;
    for (std::size_t v = 0; v < level.size(); ++v) {
        if (std::abs(unsmoothed[v]) > 0.5f) continue;
        const std::size_t g = box.gridIndex(m.dims, v);
        const bool in = m.data[g] != 0;
        if (in ? level[v] < kMaxLevelShift - kSmoothingMargin : level[v] > kSmoothingMargin - kMaxLevelShift)
            cand.push_back({g, level[v], in});
    }
    shift = volumeKeepingShift(cand);
    return cand;
}

// The bags other than b that hold every voxel of b.
std::vector<std::size_t> containersOf(const std::vector<Mask>& masks, std::size_t b, const Box& box,
                                      const Volume<std::uint8_t>& holders) {
    std::vector<std::size_t> keep;
    bool first = true;
    const Dims d = box.dims();
    for (std::size_t v = 0; v < d.count(); ++v) {
        const std::size_t g = box.gridIndex(masks[b].dims, v);
        if (!masks[b].data[g]) continue;
        if (holders.data[g] == 1) return {};
        if (first) {
            for (std::size_t c = 0; c < masks.size(); ++c)
                if (c != b && masks[c].data[g]) keep.push_back(c);
            first = false;
        } else {
            std::erase_if(keep, [&](std::size_t c) { return !masks[c].data[g]; });
        }
        if (keep.empty()) return keep;
    }
    return keep;
}

bool simpleIn(const Mask& m, std::size_t g) {
    const Eigen::Vector3i c = m.dims.coords(g);
    std::array<bool, 27> object{};
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const Eigen::Vector3i u = c + Eigen::Vector3i(dx, dy, dz);
                object[std::size_t(neighbourIndex(dx, dy, dz))] =
                    m.dims.contains(u.x(), u.y(), u.z()) && m.data[m.dims.index(u.x(), u.y(), u.z())];
            }
    return isSimplePoint(object);
}

// Whether every face neighbour of g (inside the grid) satisfies `ok`.
template <class Ok>
bool faceNeighbours(const Dims& d, std::size_t g, const Ok& ok) {
    const Eigen::Vector3i c = d.coords(g);
    for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
            Eigen::Vector3i u = c;
            u[a] += s;
            if (d.contains(u.x(), u.y(), u.z()) && !ok(d.index(u.x(), u.y(), u.z()))) return false;
        }
    return true;
}

struct BagWork {
    std::vector<Candidate> candidates;    // voxels whose side the smoothing changes, by grid index
    std::vector<std::size_t> containers;  // bags holding the whole bag
    bool wants(std::size_t g) const {     // whether the smoothing adds voxel g to the bag
        const auto it = std::lower_bound(candidates.begin(), candidates.end(), g,
                                         [](const Candidate& k, std::size_t v) { return k.voxel < v; });
        return it != candidates.end() && it->voxel == g && !it->inside;
    }
};

// The bags beside voxel g (holding a face neighbour) other than b, its containers and bags inside it.
std::vector<std::size_t> bagsBeside(const std::vector<Mask>& masks, const std::vector<BagWork>& work, std::size_t b,
                                    std::size_t g) {
    std::vector<std::size_t> out;
    for (std::size_t x = 0; x < masks.size(); ++x) {
        if (x == b || std::find(work[b].containers.begin(), work[b].containers.end(), x) != work[b].containers.end())
            continue;
        if (!faceNeighbours(masks[x].dims, g, [&](std::size_t u) { return !masks[x].data[u]; })) out.push_back(x);
    }
    return out;
}

// Moves the candidates of bag b whose change keeps its topology and the layout. A voxel leaves
// the bag only when it holds no bag inside this one and touches none; beside another bag it goes
// to that bag (when that bag's smoothing takes it), so bags that touch never open a gap. A voxel
// joins the bag only when it lies in no other bag but the containers, with its face neighbours
// inside them all.
void applyChanges(std::vector<Mask>& masks, std::size_t b, const std::vector<BagWork>& work, bool adding,
                  Volume<std::uint8_t>& holders, std::vector<BoundarySmoothingReport>& reps) {
    Mask& m = masks[b];
    const BagWork& w = work[b];
    const std::size_t own = w.containers.size();
    const auto inContainers = [&](std::size_t g) {
        return std::all_of(w.containers.begin(), w.containers.end(), [&](std::size_t c) { return masks[c].data[g]; });
    };
    for (const Candidate& k : w.candidates) {
        if (k.inside == adding) continue;
        const std::size_t g = k.voxel;
        if (adding && m.data[g]) continue;  // given by a bag beside it
        const bool layoutKept =
            adding ? holders.data[g] == own && inContainers(g) && faceNeighbours(m.dims, g, inContainers)
                   : holders.data[g] == own + 1 && faceNeighbours(m.dims, g, [&](std::size_t u) {
                         return !m.data[u] || holders.data[u] == own + 1;
                     });
        if (!layoutKept || !simpleIn(m, g)) {
            ++reps[b].keptForTopology;
            continue;
        }
        if (!adding) {
            const std::vector<std::size_t> beside = bagsBeside(masks, work, b, g);
            if (!beside.empty()) {
                const auto taker = std::find_if(beside.begin(), beside.end(), [&](std::size_t x) {
                    return work[x].containers == w.containers && work[x].wants(g) && simpleIn(masks[x], g);
                });
                if (taker == beside.end()) {
                    ++reps[b].keptForTopology;
                    continue;
                }
                masks[*taker].data[g] = 1;
                holders.data[g] = std::uint8_t(holders.data[g] + 1);
                ++reps[*taker].added;
            }
        }
        m.data[g] = adding ? 1 : 0;
        holders.data[g] = std::uint8_t(holders.data[g] + (adding ? 1 : -1));
        ++(adding ? reps[b].added : reps[b].removed);
    }
}

}  // namespace

std::vector<BoundarySmoothingReport> smoothBoundaries(std::vector<Mask>& masks, const std::vector<double>& sigmaVoxels,
                                                      int threads) {
    std::vector<BoundarySmoothingReport> reports(masks.size());
    if (std::none_of(sigmaVoxels.begin(), sigmaVoxels.end(), [](double s) { return s > 0; })) return reports;
    const Dims& grid = masks.front().dims;
    Volume<std::uint8_t> holders(grid, 0);
    for (const Mask& m : masks)
        for (std::size_t v = 0; v < grid.count(); ++v) holders.data[v] = std::uint8_t(holders.data[v] + m.data[v]);

    std::vector<BagWork> work(masks.size());
    for (std::size_t b = 0; b < masks.size(); ++b) {
        BoundarySmoothingReport& rep = reports[b];
        rep.voxelsBefore = rep.voxelsAfter = std::size_t(std::count(masks[b].data.begin(), masks[b].data.end(), 1));
        if (!(b < sigmaVoxels.size() && sigmaVoxels[b] > 0) || rep.voxelsBefore == 0) continue;
        const double width = sigmaVoxels[b];
        const Box box = boxAround(masks[b], int(std::ceil(3.0 * width)) + 2);
        const std::vector<float> unsmoothed = signedDistance(masks[b], box, threads);
        // Narrower where the bag is too thin for the width to keep its volume, down to kMinWidth.
        for (double sigma = width; sigma >= kMinWidth * 0.999; sigma *= kWidthStep) {
            work[b].candidates = planChanges(masks[b], box, unsmoothed, sigma, rep.levelShiftVoxels);
            const long long net = netChange(work[b].candidates, rep.levelShiftVoxels);
            rep.widthVoxels = sigma;
            const bool shiftFree = std::abs(rep.levelShiftVoxels) < kMaxLevelShift;  // not held at its bound
            if (shiftFree && double(std::llabs(net)) <= kVolumeTolerance * double(rep.voxelsBefore)) break;
            work[b].candidates.clear();
            rep.widthVoxels = rep.levelShiftVoxels = 0;
        }
        const double c = rep.levelShiftVoxels;
        std::erase_if(work[b].candidates, [&](const Candidate& k) {
            return k.inside ? !(k.level + c < -kSmoothingMargin) : !(k.level + c > kSmoothingMargin);
        });
        work[b].containers = containersOf(masks, b, box, holders);
    }
    // Every bag gives up voxels before any takes new ones, so that bags which touch trade the voxels between them.
    for (const bool adding : {false, true})
        for (std::size_t b = 0; b < masks.size(); ++b) applyChanges(masks, b, work, adding, holders, reports);
    for (std::size_t b = 0; b < masks.size(); ++b)
        reports[b].voxelsAfter = reports[b].voxelsBefore + reports[b].added - reports[b].removed;
    return reports;
}

}  // namespace bop::shape
