#include "app/scene/Placement.hpp"

#include "core/Construction.hpp"
#include "core/Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop::app {

using namespace core;  // placement sets the step's particles on the model's species
namespace {

constexpr int kLatticeOffsets = 8;  // shifts of a volume's lattice tried

double unit(std::uint64_t h) {
    return double(h >> 11) * 0x1.0p-53;
}  // [0, 1)

// Points by cell over a box, for "is a point within d of x" with d at most the cell size. At most
// about 2^24 cells: a big box gets wider cells.
class PointGrid {
public:
    PointGrid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double reach) : lo_(lo) {
        const Eigen::Vector3d size = (hi - lo).cwiseMax(1e-9);
        cell_ = std::max(reach, std::cbrt(size.prod() / double(1 << 24)));
        n_ = (size / cell_).array().ceil().cast<int>().max(1).matrix();
        head_.assign(std::size_t(n_.prod()), -1);
    }
    void insert(const Eigen::Vector3d& x) {
        const std::size_t c = index(cellOf(x));
        next_.push_back(head_[c]);
        pts_.push_back(x);
        head_[c] = int(pts_.size() - 1);
    }
    bool anyWithin(const Eigen::Vector3d& x, double d) const {
        const Eigen::Vector3i c = cellOf(x);
        const double d2 = d * d;
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const Eigen::Vector3i k = c + Eigen::Vector3i(dx, dy, dz);
                    if ((k.array() < 0).any() || (k.array() >= n_.array()).any()) continue;
                    for (int j = head_[index(k)]; j >= 0; j = next_[std::size_t(j)])
                        if ((pts_[std::size_t(j)] - x).squaredNorm() < d2) return true;
                }
        return false;
    }

private:
    Eigen::Vector3i cellOf(const Eigen::Vector3d& x) const {
        return ((x - lo_) / cell_).array().floor().cast<int>().max(0).min(n_.array() - 1).matrix();
    }
    std::size_t index(const Eigen::Vector3i& k) const {
        return (std::size_t(k.z()) * std::size_t(n_.y()) + std::size_t(k.y())) * std::size_t(n_.x()) +
               std::size_t(k.x());
    }
    Eigen::Vector3d lo_;
    double cell_ = 1;
    Eigen::Vector3i n_;
    std::vector<int> head_, next_;
    std::vector<Eigen::Vector3d> pts_;
};

// Whether voxel c lies outside the bag whose surface species is s (beyond the grid too).
bool outsideBag(const GradientMap& m, int s, const Eigen::Vector3i& c) {
    const Dims& d = m.dims();
    return !d.contains(c.x(), c.y(), c.z()) || !m.inBag(d.index(c.x(), c.y(), c.z()), bagOfSpecies(s));
}

// Whether voxel c lies in the bag of surface species s beneath its shell: the bag's own volume
// or a bag inside it (the shell's inner side).
bool beneathShell(const GradientMap& m, int s, const Eigen::Vector3i& c) {
    const Dims& d = m.dims();
    if (!d.contains(c.x(), c.y(), c.z())) return false;
    const std::size_t v = d.index(c.x(), c.y(), c.z());
    return m.occ[v] != s && m.inBag(v, bagOfSpecies(s));
}

// Whether the face of shell voxel c towards `step` along axis a is an outer face (outside the
// bag beyond it) or, `inner`, an inner one (beneath the shell beyond it).
bool shellFace(const GradientMap& m, int s, const Eigen::Vector3i& c, int a, int step, bool inner) {
    const Eigen::Vector3i w = c + step * Eigen::Vector3i::Unit(a);
    return inner ? beneathShell(m, s, w) : outsideBag(m, s, w);
}

// Whether that face lies in a flat patch of such faces (its 8 neighbours in the plane, shell
// voxels too, have one): a plane along the axes, whose faces count whole, where the smoothed
// normal would tilt near an edge.
bool flatFace(const GradientMap& m, int s, const Eigen::Vector3i& c, int a, int step, bool inner) {
    const int b = (a + 1) % 3, e = (a + 2) % 3;
    const Dims& d = m.dims();
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j) {
            const Eigen::Vector3i w = c + i * Eigen::Vector3i::Unit(b) + j * Eigen::Vector3i::Unit(e);
            if (!d.contains(w.x(), w.y(), w.z()) || m.occ[d.index(w.x(), w.y(), w.z())] != s ||
                !shellFace(m, s, w, a, step, inner))
                return false;
        }
    return true;
}

struct Candidate {
    std::uint64_t key;
    Eigen::Vector3d pos;
    std::size_t voxel;  // index in the map
};

// Candidates in key order taken when none taken lies within d; the indices taken.
std::vector<std::size_t> adsorb(const std::vector<Candidate>& c, double d, const Eigen::Vector3d& hi) {
    PointGrid grid(Eigen::Vector3d::Zero(), hi, d);
    std::vector<std::size_t> taken;
    for (std::size_t k = 0; k < c.size(); ++k) {
        if (grid.anyWithin(c[k].pos, d)) continue;
        grid.insert(c[k].pos);
        taken.push_back(k);
    }
    return taken;
}

}  // namespace

Placement placeParticles(const Model& model, const GradientMap& m, const PlacementParams& params) {
    const Dims& dims = m.dims();
    if (m.origin != Eigen::Vector3i::Zero() || dims.count() != m.wholeDims().count())
        throw std::invalid_argument("placement needs the whole gradient map, not a window");
    const double h = voxelLength(m.r0Voxels);
    const Eigen::Vector3d hi = Eigen::Vector3d(dims.nx, dims.ny, dims.nz) * h;
    Placement out;
    std::uint64_t nextId = 1;

    // Surface species first: the volume sites keep their distance from them.
    PointGrid surfaceGrid(Eigen::Vector3d::Zero(), hi, params.gapR0 * kR0);
    for (int s = 1; s <= model.speciesCount(); ++s) {
        if (!model.isSurface(s)) continue;
        std::vector<Candidate> cand;
        double area = 0;
        for (std::size_t v = 0; v < m.occ.size(); ++v) {
            if (m.occ[v] != s) continue;
            const Eigen::Vector3i c = dims.coords(v);
            const Eigen::Vector3d n = m.nearestSurface(v).normal.cast<double>();
            // Faces: the shell's outer faces. Mid-shell: the area midway between its outer and
            // inner faces, where the map holds the sheet (the shell voxels' centres), half the
            // sum of both.
            // Where the bag is a membrane (thinner than 2 r0), the outer faces on both sides hold
            // one sheet between them: each counts half.
            const bool mid = params.sheetArea == SheetArea::MidShell;
            const bool membrane = params.membrane && (*params.membrane)[v];
            for (int a = 0; a < 3; ++a)
                for (int step : {-1, 1})
                    for (bool inner : {false, true})
                        if ((mid || !inner) && shellFace(m, s, c, a, step, inner))
                            area += (mid || membrane ? 0.5 : 1.0) * h * h *
                                    (flatFace(m, s, c, a, step, inner) ? 1.0 : 1.0 / std::max(1.0, n.lpNorm<1>()));
            const std::uint64_t key = mixHash(params.seed, 0x91aceULL, std::uint64_t(s), std::uint64_t(v));
            Eigen::Vector3d jitter(unit(mixHash(key, 1)) - 0.5, unit(mixHash(key, 2)) - 0.5,
                                   unit(mixHash(key, 3)) - 0.5);
            if (params.flatSheet && n.squaredNorm() > 0) jitter -= jitter.dot(n) * n / n.squaredNorm();
            cand.push_back({key, (c.cast<double>() + Eigen::Vector3d::Constant(0.5) + 0.6 * jitter) * h, v});
        }
        if (cand.empty()) continue;
        std::sort(cand.begin(), cand.end(), [](const Candidate& a, const Candidate& b) {
            return a.key != b.key ? a.key < b.key : a.voxel < b.voxel;
        });
        const double ideal = area / (std::sqrt(3.0) / 2 * kR0 * kR0);
        // The spacing whose count is nearest the ideal: the count falls as d grows.
        double lo = 0.3 * kR0, up = 1.5 * kR0;
        std::vector<std::size_t> best = adsorb(cand, up, hi);
        for (int it = 0; it < 14; ++it) {
            const double d = 0.5 * (lo + up);
            std::vector<std::size_t> taken = adsorb(cand, d, hi);
            const double miss = std::abs(double(taken.size()) - ideal),
                         bestMiss = std::abs(double(best.size()) - ideal);
            if (miss < bestMiss) best = taken;
            (double(taken.size()) > ideal ? lo : up) = d;
            if (miss <= 0.002 * ideal) break;
        }
        std::sort(best.begin(), best.end());
        for (const std::size_t k : best) {
            const Eigen::Vector3d n = m.nearestSurface(cand[k].voxel).normal.cast<double>();
            out.particles.add(cand[k].pos, s, nextId++, orientationFor(n));
            surfaceGrid.insert(cand[k].pos);
        }
        out.species.push_back({s, best.size(), ideal, area});
    }

    const double a = std::sqrt(2.0) * kR0;  // fcc cube edge for nearest neighbours at r0
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    for (int s = 1; s <= model.speciesCount(); ++s) {
        if (model.isSurface(s)) continue;
        Eigen::Vector3i vlo = Eigen::Vector3i::Constant(dims.nx + dims.ny + dims.nz),
                        vhi = Eigen::Vector3i::Constant(-1);
        std::size_t voxels = 0;
        for (std::size_t v = 0; v < m.occ.size(); ++v) {
            if (m.occ[v] != s) continue;
            const Eigen::Vector3i c = dims.coords(v);
            vlo = vlo.cwiseMin(c);
            vhi = vhi.cwiseMax(c);
            ++voxels;
        }
        if (voxels == 0) continue;
        const Eigen::Vector3i c0 =
            (vlo.cast<double>() * h / a).array().floor().cast<int>().matrix() - Eigen::Vector3i::Ones();
        const Eigen::Vector3i c1 =
            ((vhi.cast<double>() + Eigen::Vector3d::Ones()) * h / a).array().ceil().cast<int>().matrix();
        // The sites of the lattice shifted by `offset` (cube edges) that the species may hold.
        const auto sites = [&](const Eigen::Vector3d& offset) {
            std::vector<Eigen::Vector3d> out;
            for (int k = c0.z(); k <= c1.z(); ++k)
                for (int j = c0.y(); j <= c1.y(); ++j)
                    for (int i = c0.x(); i <= c1.x(); ++i)
                        for (const auto& b : basis) {
                            const Eigen::Vector3d x = (Eigen::Vector3d(i + b[0], j + b[1], k + b[2]) + offset) * a;
                            const Eigen::Vector3i c = (x / h).array().floor().cast<int>().matrix();
                            if (!dims.contains(c.x(), c.y(), c.z()) || m.occ[dims.index(c.x(), c.y(), c.z())] != s)
                                continue;
                            if (!surfaceGrid.anyWithin(x, params.gapR0 * kR0)) out.push_back(x);
                        }
            return out;
        };
        // Of kLatticeOffsets hashed shifts, the one that holds the most sites (the first of equals).
        std::vector<Eigen::Vector3d> best;
        for (int t = 0; t < kLatticeOffsets; ++t) {
            const std::uint64_t key = mixHash(params.seed, 0xfccULL, std::uint64_t(s), std::uint64_t(t));
            std::vector<Eigen::Vector3d> x =
                sites(Eigen::Vector3d(unit(mixHash(key, 1)), unit(mixHash(key, 2)), unit(mixHash(key, 3))));
            if (x.size() > best.size()) best = std::move(x);
        }
        for (const Eigen::Vector3d& x : best) out.particles.add(x, s, nextId++);
        const std::size_t placed = best.size();
        const double volume = double(voxels) * h * h * h;
        out.species.push_back({s, placed, volume / (kR0 * kR0 * kR0 / std::sqrt(2.0)), volume});
    }
    std::sort(out.species.begin(), out.species.end(),
              [](const PlacedSpecies& x, const PlacedSpecies& y) { return x.species < y.species; });
    return out;
}

}  // namespace bop::app
