#include "ClusterPairProto.hpp"

#include "core/OrientedTerms.hpp"
#include "core/TargetClones.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>

namespace bop::tools {

using core::load16;
using core::V16F;
using core::V16FMask;
using core::Xyz;

namespace {

[[gnu::always_inline]] inline void add16(float* p, V16F v) {
    const V16F was = load16(p);
    const V16F now = was + v;
    std::memcpy(p, &now, sizeof now);
}

// Lanes 4a + b with a < b: a cluster with itself counts each pair once and no particle with itself.
V16FMask selfLanes() {
    V16FMask m;
    for (int l = 0; l < 16; ++l) m[l] = l / 4 < l % 4 ? -1 : 0;
    return m;
}

struct Box {
    Eigen::Vector3d lo, hi;
};

double gap(const Box& a, const Box& b, const Eigen::Vector3d& shift) {  // shortest distance, b shifted
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double g = std::max({0.0, a.lo[k] - (b.hi[k] + shift[k]), (b.lo[k] + shift[k]) - a.hi[k]});
        d2 += g * g;
    }
    return std::sqrt(d2);
}

// reset() then pass() `repeats` times, pass() alone timed (it returns the pairs in range); sum()
// the results of the last.
template <class Reset, class Pass, class Sum>
ClusterPass timed(const ClusterSet& set, int repeats, Reset reset, Pass pass, Sum sum) {
    ClusterPass out;
    out.seconds = 1e30;
    for (int r = 0; r < repeats; ++r) {
        reset();
        const auto t0 = std::chrono::steady_clock::now();
        out.inRange = pass();
        out.seconds =
            std::min(out.seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    out.checksum = sum();
    out.computed = 16 * set.entries.size();
    return out;
}

double sumOf(const std::vector<float>* f) {  // three components
    double s = 0;
    for (int k = 0; k < 3; ++k) s += std::accumulate(f[k].begin(), f[k].end(), 0.0);
    return s;
}

}  // namespace

ClusterSet buildClusters(const std::vector<Eigen::Vector3d>& pos, const std::vector<Eigen::Vector3d>& normal,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool periodic, double range) {
    ClusterSet s;
    const std::size_t n = pos.size();
    const Eigen::Vector3d size = hi - lo;
    // A cluster's edge, were it a cube at the particles' density where they are (a bag leaves most
    // of its box empty): the occupied volume counted in cells of about 2 r0 (each holds a particle
    // of any bulk material at r0 spacing, wherever it is cut).
    const Eigen::Vector3i cells = (size / (2 * kR0)).array().floor().cast<int>().max(1);
    const Eigen::Vector3d edge = size.cwiseQuotient(cells.cast<double>());
    std::vector<char> occupied(std::size_t(cells.prod()), 0);
    for (const auto& x : pos) {
        const Eigen::Vector3i c =
            (x - lo).cwiseQuotient(edge).cast<int>().cwiseMax(0).cwiseMin(cells - Eigen::Vector3i::Ones());
        occupied[std::size_t((c.x() * cells.y() + c.y()) * cells.z() + c.z())] = 1;
    }
    const double volume = edge.prod() * double(std::count(occupied.begin(), occupied.end(), 1));
    const double width = std::cbrt(kCluster * volume / double(n));
    // Columns 1.1 times the cube's edge: of 1.0, 1.1, 1.2, 1.3, 1.4 and 1.6 it gave the LJ loop's
    // clusters their best share on the fcc box (0.13-0.14, against 0.09 at 1.0) and within 0.01
    // of the best on the torus.
    const int cols = std::max(1, int(std::lround(std::min(size.x(), size.y()) / (1.1 * width))));
    const auto column = [&](const Eigen::Vector3d& x) {
        const int cx = std::clamp(int((x.x() - lo.x()) / size.x() * cols), 0, cols - 1);
        const int cy = std::clamp(int((x.y() - lo.y()) / size.y() * cols), 0, cols - 1);
        return cx * cols + cy;
    };
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const int ca = column(pos[a]), cb = column(pos[b]);
        return ca != cb ? ca < cb : pos[a].z() < pos[b].z();
    });
    std::vector<std::vector<std::uint32_t>> inColumn(std::size_t(cols) * cols);
    for (std::size_t k = 0; k < n;) {  // each column's particles four at a time, the last padded
        const int c = column(pos[order[k]]);
        inColumn[std::size_t(c)].push_back(std::uint32_t(s.clusters++));
        for (int a = 0; a < kCluster; ++a) {
            const bool here = k < n && column(pos[order[k]]) == c;
            s.particle.push_back(here ? std::int64_t(order[k++]) : -1);
        }
    }
    std::vector<Box> box(s.clusters);
    for (auto* v : {s.iPos, s.jPos, s.iNormal, s.jNormal})
        for (int k = 0; k < 3; ++k) v[k].assign(16 * s.clusters, 0.0f);
    for (std::size_t c = 0; c < s.clusters; ++c) {
        box[c] = {Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
        for (int a = 0; a < kCluster; ++a) {
            const std::int64_t p = s.particle[kCluster * c + std::size_t(a)];
            // Padding sits far away, 10 length units from any other (never within range), normal z.
            const Eigen::Vector3d far(-1e5 - 10.0 * double(kCluster * c + std::size_t(a)), -1e5, -1e5);
            const Eigen::Vector3d x = p >= 0 ? pos[std::size_t(p)] : far;
            const Eigen::Vector3d nrm = p >= 0 ? normal[std::size_t(p)] : Eigen::Vector3d::UnitZ();
            if (p >= 0) box[c].lo = box[c].lo.cwiseMin(x), box[c].hi = box[c].hi.cwiseMax(x);
            for (int k = 0; k < 3; ++k)
                for (int b = 0; b < kCluster; ++b) {
                    s.iPos[k][16 * c + std::size_t(4 * a + b)] = float(x[k]);
                    s.jPos[k][16 * c + std::size_t(4 * b + a)] = float(x[k]);
                    s.iNormal[k][16 * c + std::size_t(4 * a + b)] = float(nrm[k]);
                    s.jNormal[k][16 * c + std::size_t(4 * b + a)] = float(nrm[k]);
                }
        }
    }
    const int reach = int(std::ceil(range / std::min(size.x() / cols, size.y() / cols))) + 1;
    const int zShifts = periodic ? 1 : 0;
    s.start.push_back(0);
    for (std::size_t ci = 0; ci < s.clusters; ++ci) {
        const int c = column(box[ci].lo);
        const int cx = c / cols, cy = c % cols;
        for (int dx = -reach; dx <= reach; ++dx)
            for (int dy = -reach; dy <= reach; ++dy) {
                const int x = cx + dx, y = cy + dy;
                if (!periodic && (x < 0 || y < 0 || x >= cols || y >= cols)) continue;
                const int wx = (x % cols + cols) % cols, wy = (y % cols + cols) % cols;
                for (const std::uint32_t cj : inColumn[std::size_t(wx * cols + wy)]) {
                    if (cj < ci) continue;
                    for (int sz = -zShifts; sz <= zShifts; ++sz) {
                        const Eigen::Vector3d shift(size.x() * ((x - wx) / cols), size.y() * ((y - wy) / cols),
                                                    size.z() * sz);
                        const bool self = cj == ci && shift.isZero();
                        // A cluster with its own image: the shift and its opposite list the same pairs.
                        if (cj == ci && !self &&
                            std::make_tuple(shift.x(), shift.y(), shift.z()) < std::make_tuple(0.0, 0.0, 0.0))
                            continue;
                        if (gap(box[ci], box[cj], shift) >= range) continue;
                        s.entries.push_back({cj, {float(shift.x()), float(shift.y()), float(shift.z())}, self});
                    }
                }
            }
        s.start.push_back(std::uint32_t(s.entries.size()));
    }
    return s;
}

namespace {
// One pass of the LJ kernel: forces into fi (i side, repeated) and fj (j side, tiled), each
// component 16 floats a cluster; returns the pairs in range.
BOP_HOT_LOOP std::size_t ljPass(const ClusterSet& set, const core::LjForm& lj, std::vector<float>* fi,
                                std::vector<float>* fj) {
    const float cut2 = float(lj.cutoff2()), fShift = float(lj.forceShift()), rOn = float(lj.switchOn()),
                invWidth = float(lj.invSwitchWidth());
    const V16FMask self = selfLanes(), all = self | ~self;
    V16FMask count = {};
    for (std::size_t ci = 0; ci < set.clusters; ++ci) {
        const V16F xi = load16(&set.iPos[0][16 * ci]), yi = load16(&set.iPos[1][16 * ci]),
                   zi = load16(&set.iPos[2][16 * ci]);
        V16F fx = {}, fy = {}, fz = {};
        for (std::uint32_t e = set.start[ci]; e < set.start[ci + 1]; ++e) {
            const ClusterSet::Entry& en = set.entries[e];
            const std::size_t j = 16 * std::size_t(en.j);
            const V16F dx = load16(&set.jPos[0][j]) + en.shift[0] - xi;
            const V16F dy = load16(&set.jPos[1][j]) + en.shift[1] - yi;
            const V16F dz = load16(&set.jPos[2][j]) + en.shift[2] - zi;
            const V16F r2 = dx * dx + dy * dy + dz * dz;
            const V16FMask in = (r2 < core::splat16(cut2)) & (en.self ? self : all);
            const V16F q2 = core::select(in, r2, core::splat16(1.0f));
            const V16F inv2 = 1.0f / q2;
            const V16F r = core::vsqrt(q2);
            const V16F f = (4.5f * inv2 - 1.5f) * inv2 - fShift;
            const V16F t = core::atLeast((r - rOn) * invWidth, 0.0f);
            const V16F fr = core::select(in, f * (1.0f + t * t * (2.0f * t - 3.0f)) * (r * inv2), core::splat16(0.0f));
            fx -= fr * dx, fy -= fr * dy, fz -= fr * dz;
            add16(&fj[0][j], fr * dx), add16(&fj[1][j], fr * dy), add16(&fj[2][j], fr * dz);
            count -= in;  // a lane in range is -1
        }
        add16(&fi[0][16 * ci], fx), add16(&fi[1][16 * ci], fy), add16(&fi[2][16 * ci], fz);
    }
    std::size_t n = 0;
    for (int l = 0; l < 16; ++l) n += std::size_t(count[l]);
    return n;
}
}  // namespace

ClusterPass ljClusterPass(const ClusterSet& set, const core::LjForm& lj, int repeats) {
    std::vector<float> fi[3], fj[3];
    return timed(
        set, repeats,
        [&] {
            for (int k = 0; k < 3; ++k) fi[k].assign(set.iPos[k].size(), 0.0f), fj[k].assign(set.iPos[k].size(), 0.0f);
        },
        [&] { return ljPass(set, lj, fi, fj); }, [&] { return sumOf(fi) + sumOf(fj); });
}

namespace {
// orientedPair's results for sixteen lanes: i's into accumulators, j's into the j cluster's tiles.
struct ClusterSink {
    V16FMask in;
    Xyz<V16F>& fiAcc;
    Xyz<V16F>& tiAcc;
    float* fjAt[3];
    float* tjAt[3];
    V16F& virialSum;
    [[gnu::always_inline]] V16F keep(V16F v) const { return core::select(in, v, core::splat16(0.0f)); }
    [[gnu::always_inline]] void fj(const Xyz<V16F>& v) {
        add16(fjAt[0], keep(v.x)), add16(fjAt[1], keep(v.y)), add16(fjAt[2], keep(v.z));
    }
    [[gnu::always_inline]] void tj(const Xyz<V16F>& v) {
        add16(tjAt[0], keep(v.x)), add16(tjAt[1], keep(v.y)), add16(tjAt[2], keep(v.z));
    }
    [[gnu::always_inline]] void fi(const Xyz<V16F>& v) {
        fiAcc.x += keep(v.x), fiAcc.y += keep(v.y), fiAcc.z += keep(v.z);
    }
    [[gnu::always_inline]] void ti(const Xyz<V16F>& v) {
        tiAcc.x += keep(v.x), tiAcc.y += keep(v.y), tiAcc.z += keep(v.z);
    }
    [[gnu::always_inline]] void virial(V16F v) { virialSum += keep(v); }
    [[gnu::always_inline]] void energy(V16F) {}
};

// One pass of the oriented kernel: forces and torques into fi, ti (i side) and fj, tj (j side);
// returns the pairs in range and adds the virial's lanes to `virial`.
BOP_HOT_LOOP std::size_t orientedPass(const ClusterSet& set, const core::OrientedWeight& w, std::vector<float>* fi,
                                      std::vector<float>* fj, std::vector<float>* ti, std::vector<float>* tj,
                                      double& virialSum) {
    const float cut2 = float(w.cutoff2());
    const core::PsiConstantsOf<float> psiK = core::toFloat(w.constants());
    const V16FMask self = selfLanes(), all = self | ~self;
    const V16F one = core::splat16(1.0f);
    const core::OrientedWeights<V16F> k{one, one, one, one, one, one, one, one, one, one};
    V16FMask count = {};
    V16F virial = {};
    for (std::size_t ci = 0; ci < set.clusters; ++ci) {
        const std::size_t i = 16 * ci;
        const Xyz<V16F> xi{load16(&set.iPos[0][i]), load16(&set.iPos[1][i]), load16(&set.iPos[2][i])};
        const Xyz<V16F> ni{load16(&set.iNormal[0][i]), load16(&set.iNormal[1][i]), load16(&set.iNormal[2][i])};
        Xyz<V16F> fiAcc{}, tiAcc{};
        for (std::uint32_t e = set.start[ci]; e < set.start[ci + 1]; ++e) {
            const ClusterSet::Entry& en = set.entries[e];
            const std::size_t j = 16 * std::size_t(en.j);
            const Xyz<V16F> r{load16(&set.jPos[0][j]) + en.shift[0] - xi.x,
                              load16(&set.jPos[1][j]) + en.shift[1] - xi.y,
                              load16(&set.jPos[2][j]) + en.shift[2] - xi.z};
            const Xyz<V16F> nj{load16(&set.jNormal[0][j]), load16(&set.jNormal[1][j]), load16(&set.jNormal[2][j])};
            const V16F r2 = r.x * r.x + r.y * r.y + r.z * r.z;
            const V16FMask in = (r2 < core::splat16(cut2)) & (en.self ? self : all);
            const V16F q2 = core::select(in, r2, one);
            const V16F rlen = core::vsqrt(q2);
            ClusterSink sink{in,    fiAcc, tiAcc, {&fj[0][j], &fj[1][j], &fj[2][j]}, {&tj[0][j], &tj[1][j], &tj[2][j]},
                             virial};
            core::orientedPair<false>(r, q2, core::inverseOrZero(rlen), core::normalPair(r, ni, nj),
                                      core::orientedPsi(q2, rlen, psiK), one, k, sink);
            count -= in;
        }
        add16(&fi[0][i], fiAcc.x), add16(&fi[1][i], fiAcc.y), add16(&fi[2][i], fiAcc.z);
        add16(&ti[0][i], tiAcc.x), add16(&ti[1][i], tiAcc.y), add16(&ti[2][i], tiAcc.z);
    }
    std::size_t n = 0;
    for (int l = 0; l < 16; ++l) n += std::size_t(count[l]), virialSum += double(virial[l]);
    return n;
}

}  // namespace

ClusterPass orientedClusterPass(const ClusterSet& set, const core::OrientedWeight& w, int repeats) {
    std::vector<float> fi[3], fj[3], ti[3], tj[3];
    double virial = 0;
    return timed(
        set, repeats,
        [&] {
            for (std::vector<float>* v : {fi, fj, ti, tj})
                for (int c = 0; c < 3; ++c) v[c].assign(set.iPos[c].size(), 0.0f);
            virial = 0;
        },
        [&] { return orientedPass(set, w, fi, fj, ti, tj, virial); },
        [&] {
            double sum = virial;
            for (const std::vector<float>* v : {fi, fj, ti, tj}) sum += sumOf(v);
            return sum;
        });
}

}  // namespace bop::tools
