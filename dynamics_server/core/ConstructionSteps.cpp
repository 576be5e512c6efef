#include "ConstructionSteps.hpp"

#include "CellList.hpp"
#include "Integrator.hpp"
#include "Threads.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::core {
namespace {

constexpr std::size_t kScanBlock = 4096;  // voxels or particles per block of a scan on the threads

double unit(std::uint64_t h) {
    return double(h >> 11) * 0x1.0p-53;
}  // [0, 1)

// Spatial lookup over a set of points with one query radius (or less). Cells are at least
// the radius wide, and wider in big boxes so that the grid stays under about 10^7 cells.
// Points outside a non-periodic box fall into its border cells (CellList), which keeps the
// lookup exact for a rank's halo.
struct PointGrid {
    CellList cells;
    void build(const Box& box, double radius, const std::vector<Eigen::Vector3d>& pts) {
        cells.build(box, std::max(radius, box.size().maxCoeff() / 200.0), pts);
    }
    // Calls f(index, distance^2) for every point within `radius` of x until f returns true;
    // returns whether it did.
    template <class F>
    bool anyNear(const Eigen::Vector3d& x, double radius, const std::vector<Eigen::Vector3d>& pts, F f) const {
        thread_local std::vector<CellList::Neighbour> near;  // scratch: the scans run on threads
        cells.around(cells.cellOf(x), 1, near);
        const double r2 = radius * radius;
        for (const auto& nb : near)
            for (std::uint32_t k = cells.start(nb.cell); k < cells.start(nb.cell + 1); ++k) {
                const std::uint32_t j = cells.order()[k];
                const double d2 = (pts[j] + nb.shift - x).squaredNorm();
                if (d2 < r2 && f(j, d2)) return true;
            }
        return false;
    }
};

Eigen::Vector3d voxelCentre(const GradientMap& m, std::size_t v) {
    return (m.wholeCoords(v).cast<double>() + Eigen::Vector3d::Constant(0.5)) * voxelLength(m.r0Voxels);
}

// Which voxel seeds a species (the smaller key wins). Surface species: a surface voxel chosen by
// the hash. Volume species: the deepest voxel (farthest from any surface), so the seed does not
// die next to a surface particle.
std::pair<long long, std::uint64_t> seedKey(const ConstructionParams& params, const GradientMap& m, bool surface,
                                            int species, std::size_t v) {
    return {surface ? 0 : -m.delta(v).squaredNorm(),
            mixHash(params.seed, 0x5eedULL, std::uint64_t(species), m.wholeIndex(v))};
}

}  // namespace

std::vector<DeathMark> markDeaths(const ConstructionParams& params, const ConstructionView& view, long long step) {
    const Particles& p = view.seen;
    const double d = params.deathR0 * kR0;
    PointGrid grid;
    grid.build(view.box, d, p.pos);
    // Every particle on its own, on the threads, in fixed blocks; a victim is marked whichever
    // block finds it, so the marks do not depend on the thread count.
    std::vector<std::vector<std::uint32_t>> victims(blockCount(p.size(), kScanBlock));
    forBlocks(p.size(), kScanBlock, [&](std::size_t b, std::size_t i0, std::size_t i1) {
        for (std::size_t i = i0; i < i1; ++i)
            grid.anyNear(p.pos[i], d, p.pos, [&](std::uint32_t j, double) {
                if (j <= i || (j >= view.owned && i >= view.owned)) return false;  // each pair once; own ones only
                const bool si = view.model.isSurface(p.species[i]), sj = view.model.isSurface(p.species[j]);
                std::size_t victim;
                if (si != sj)
                    victim = si ? j : i;  // surface + volume: the volume particle dies
                else
                    victim = p.id[i] > p.id[j] ? i : j;
                if (victim < view.owned) victims[b].push_back(std::uint32_t(victim));
                return false;
            });
    });
    std::vector<char> marked(view.owned, 0);
    for (const auto& v : victims)
        for (const std::uint32_t i : v) marked[i] = 1;
    std::vector<DeathMark> out;
    for (std::size_t i = 0; i < view.owned; ++i)
        if (marked[i]) out.push_back({mixHash(params.seed, std::uint64_t(step), p.id[i]), p.id[i], p.species[i]});
    return out;
}

std::vector<std::uint64_t> chooseDeaths(const ConstructionParams& params, std::vector<DeathMark> marks,
                                        const std::vector<std::size_t>& count, const std::vector<char>& birthOn) {
    std::sort(marks.begin(), marks.end(),
              [](const DeathMark& a, const DeathMark& b) { return a.key != b.key ? a.key < b.key : a.id < b.id; });
    std::vector<std::size_t> killed(count.size(), 0);
    std::vector<std::uint64_t> die;
    for (const DeathMark& m : marks) {
        const std::size_t s = std::size_t(m.species);
        if (s >= birthOn.size() || !birthOn[s]) continue;
        const std::size_t cap = std::max<std::size_t>(1, std::size_t(std::ceil(params.capFraction * double(count[s]))));
        if (killed[s] >= cap) continue;
        ++killed[s];
        die.push_back(m.id);
    }
    std::sort(die.begin(), die.end());
    return die;
}

std::vector<BirthCandidate> birthCandidates(const ConstructionParams& params, const ConstructionView& view, int species,
                                            long long step, const std::function<bool(const Eigen::Vector3d&)>& mine) {
    const GradientMap& m = *view.map;
    const Particles& p = view.seen;
    const double h = voxelLength(m.r0Voxels);
    const double dSame = params.sameR0 * kR0, dAny = params.anyR0 * kR0, dFront = params.frontR0 * kR0;
    // Blocked: a particle closer than dAny, or one of the species closer than dSame (a small
    // grid, and most voxels of a growing bag are blocked). Front: one of the species within dFront.
    const double dClose = std::max(dSame, dAny);
    PointGrid close, far;
    close.build(view.box, dClose, p.pos);
    far.build(view.box, dFront, p.pos);
    // Every voxel on its own, on the threads, in fixed blocks joined in voxel order.
    std::vector<std::vector<BirthCandidate>> found(blockCount(m.occ.size(), kScanBlock));
    const auto scan = [&](std::size_t b, std::size_t v0, std::size_t v1) {
        for (std::size_t v = v0; v < v1; ++v) {
            if (m.occ[v] != species) continue;
            const std::uint64_t voxel = m.wholeIndex(v);
            const std::uint64_t key = mixHash(params.seed, std::uint64_t(step), std::uint64_t(species), voxel);
            const Eigen::Vector3d jitter(unit(mixHash(key, 1)) - 0.5, unit(mixHash(key, 2)) - 0.5,
                                         unit(mixHash(key, 3)) - 0.5);
            const Eigen::Vector3d c =
                (m.wholeCoords(v).cast<double>() + Eigen::Vector3d::Constant(0.5) + 0.1 * jitter) * h;
            if (!mine(c)) continue;
            const bool blocked = close.anyNear(c, dClose, p.pos, [&](std::uint32_t j, double d2) {
                return d2 < dAny * dAny || (p.species[j] == species && d2 < dSame * dSame);
            });
            if (blocked) continue;
            const bool front =
                far.anyNear(c, dFront, p.pos, [&](std::uint32_t j, double) { return p.species[j] == species; });
            if (front) found[b].push_back({c, key, voxel});
        }
    };
    forBlocks(m.occ.size(), kScanBlock, scan, 8);
    std::vector<BirthCandidate> accepted;
    for (const auto& f : found) accepted.insert(accepted.end(), f.begin(), f.end());
    return accepted;
}

std::vector<BirthCandidate> chooseBirths(const ConstructionParams& params, const Box& box,
                                         std::vector<BirthCandidate> candidates, std::size_t have) {
    // One priority round among candidates that conflict (closer than dSame): the smallest key wins.
    const double dSame = params.sameR0 * kR0;
    std::sort(candidates.begin(), candidates.end(),
              [](const BirthCandidate& a, const BirthCandidate& b) { return a.voxel < b.voxel; });
    std::vector<Eigen::Vector3d> pts;
    for (const auto& c : candidates) pts.push_back(c.pos);
    PointGrid grid;
    grid.build(box, dSame, pts);
    std::vector<BirthCandidate> winners;
    for (std::size_t a = 0; a < candidates.size(); ++a) {
        bool keep = true;
        grid.anyNear(candidates[a].pos, dSame, pts, [&](std::uint32_t b, double) {
            if (b != a && candidates[b].key < candidates[a].key) keep = false;
            return !keep;
        });
        if (keep) winners.push_back(candidates[a]);
    }
    std::sort(winners.begin(), winners.end(), [](const BirthCandidate& a, const BirthCandidate& b) {
        return a.key != b.key ? a.key < b.key : a.voxel < b.voxel;
    });
    const std::size_t cap = std::max<std::size_t>(1, std::size_t(std::ceil(params.capFraction * double(have))));
    if (winners.size() > cap) winners.resize(cap);
    return winners;
}

void addBirth(const Model& model, const GradientMap& m, Particles& p, int species, const BirthCandidate& c,
              std::uint64_t id) {
    const std::size_t v = m.voxelAt(m.wholeDims().coords(c.voxel));
    const Eigen::Vector3d n = m.nearestSurface(v).normal.cast<double>();
    p.add(c.pos, species, id, model.isSurface(species) ? orientationFor(n) : Eigen::Quaterniond::Identity());
}

std::optional<SeedChoice> defaultSeed(const ConstructionParams& params, const Model& model, const GradientMap& m,
                                      int species, const std::function<bool(const Eigen::Vector3d&)>& mine) {
    // Per fixed block of voxels on the threads (the first smallest key of each), then the blocks
    // in voxel order: the same choice as one pass, at any thread count.
    const bool surface = model.isSurface(species);
    std::vector<std::optional<SeedChoice>> bestOf(blockCount(m.occ.size(), kScanBlock));
    const auto scan = [&](std::size_t b, std::size_t v0, std::size_t v1) {
        std::optional<SeedChoice>& best = bestOf[b];
        for (std::size_t v = v0; v < v1; ++v) {
            if (m.occ[v] != species) continue;
            const std::pair<long long, std::uint64_t> key = seedKey(params, m, surface, species, v);
            if (best && !(key < best->key)) continue;
            const Eigen::Vector3d c = voxelCentre(m, v);
            if (mine(c)) best = SeedChoice{key, c};
        }
    };
    forBlocks(m.occ.size(), kScanBlock, scan, 8);
    std::optional<SeedChoice> best;
    for (const auto& c : bestOf)
        if (c && (!best || c->key < best->key)) best = c;
    return best;
}

std::vector<std::optional<SeedChoice>> seedsOfPieces(const ConstructionParams& params, const Model& model,
                                                     const GradientMap& m, int species,
                                                     const std::vector<std::uint32_t>& piece, std::uint32_t pieces) {
    if (piece.size() != m.occ.size())
        throw std::invalid_argument("pieces cover " + std::to_string(piece.size()) + " voxels, the map " +
                                    std::to_string(m.occ.size()));
    const bool surface = model.isSurface(species);
    std::vector<std::optional<SeedChoice>> best(pieces);
    for (std::size_t v = 0; v < m.occ.size(); ++v) {
        if (m.occ[v] != species || piece[v] == 0 || piece[v] > pieces) continue;
        std::optional<SeedChoice>& b = best[piece[v] - 1];
        const auto key = seedKey(params, m, surface, species, v);
        if (!b || key < b->key) b = SeedChoice{key, voxelCentre(m, v)};
    }
    return best;
}

bool crowded(const std::vector<Eigen::Vector3d>& pos, const Box& box, const Eigen::Vector3d& x, double distance) {
    const Eigen::Vector3d L = box.size();
    for (const Eigen::Vector3d& y : pos) {
        Eigen::Vector3d d = y - x;
        for (int a = 0; a < 3; ++a)
            if (box.periodic[std::size_t(a)]) d[a] -= L[a] * std::round(d[a] / L[a]);
        if (d.squaredNorm() < distance * distance) return true;
    }
    return false;
}

}  // namespace bop::core
