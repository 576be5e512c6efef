#include "Construction.hpp"

#include "CellList.hpp"
#include "Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop::core {
namespace {

std::uint64_t splitMix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

double unit(std::uint64_t h) { return double(h >> 11) * 0x1.0p-53; }  // [0, 1)

// Spatial lookup over a set of points with one query radius (or less). Cells are at least
// the radius wide, and wider in big boxes so that the grid stays under about 10^7 cells.
struct PointGrid {
    CellList cells;
    std::vector<CellList::Neighbour> near;
    void build(const Box& box, double radius, const std::vector<Eigen::Vector3d>& pts) {
        cells.build(box, std::max(radius, box.size().maxCoeff() / 200.0), pts);
    }
    // Calls f(index, distance^2) for every point within `radius` of x until f returns true;
    // returns whether it did.
    template <class F> bool anyNear(const Eigen::Vector3d& x, double radius, const std::vector<Eigen::Vector3d>& pts, F f) {
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

}  // namespace

std::uint64_t mixHash(std::uint64_t a, std::uint64_t b, std::uint64_t c, std::uint64_t d) {
    return splitMix(splitMix(splitMix(splitMix(a) ^ b) ^ c) ^ d);
}

Construction::Construction(ConstructionParams params, std::vector<ConstructionEvent> timeline, int speciesCount)
    : params_(params), timeline_(std::move(timeline)), birth_(std::size_t(speciesCount) + 1, 0) {
    std::stable_sort(timeline_.begin(), timeline_.end(),
                     [](const ConstructionEvent& a, const ConstructionEvent& b) { return a.step < b.step; });
}

void Construction::setBirth(int species, bool on) {
    if (species < 1 || std::size_t(species) >= birth_.size()) throw std::out_of_range("no such species");
    birth_[std::size_t(species)] = on;
}

Eigen::Vector3d Construction::defaultSeedPosition(const Model& model, int species) const {
    if (!model.map) throw std::invalid_argument("seeding needs a gradient map");
    const GradientMap& m = *model.map;
    // Surface species: a surface voxel chosen by the hash. Volume species: the deepest voxel
    // (farthest from any surface), so the seed does not die next to a surface particle.
    const bool surface = model.isSurface(species);
    std::size_t best = m.occ.size();
    std::pair<int, std::uint64_t> bestKey{0, ~0ULL};
    for (std::size_t v = 0; v < m.occ.size(); ++v) {
        if (m.occ[v] != species) continue;
        const std::pair<int, std::uint64_t> key{surface ? 0 : -m.delta(v).squaredNorm(),
                                                mixHash(params_.seed, 0x5eedULL, std::uint64_t(species), v)};
        if (key < bestKey) { bestKey = key; best = v; }
    }
    if (best == m.occ.size()) throw std::invalid_argument("species " + std::to_string(species) + " has no voxels in the map");
    const double h = kR0 / m.r0Voxels;
    return (m.dims().coords(best).cast<double>() + Eigen::Vector3d::Constant(0.5)) * h;
}

std::uint64_t Construction::seed(const Model& model, Particles& p, int species, const Eigen::Vector3d& position,
                                 long long step) {
    std::uint64_t voxel = 0;
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    if (model.map) {
        const GradientMap& m = *model.map;
        const double h = kR0 / m.r0Voxels;
        const Eigen::Vector3i v = (position / h).array().floor().cast<int>().max(0).min(
            Eigen::Array3i(m.dims().nx - 1, m.dims().ny - 1, m.dims().nz - 1)).matrix();
        voxel = m.dims().index(v.x(), v.y(), v.z());
        n = m.nearestSurface(voxel).normal.cast<double>();
    }
    const std::uint64_t gid = (std::uint64_t(step + 1) << 32) | voxel;
    p.add(position, species, gid, model.isSurface(species) ? orientationFor(n) : Eigen::Quaterniond::Identity());
    return gid;
}

ConstructionCounts Construction::update(const Model& model, Particles& p, long long step) {
    for (const auto& e : timeline_) {
        if (e.step != step) continue;
        if (e.action == ConstructionEvent::Action::Seed) {
            const double h = model.map ? kR0 / model.map->r0Voxels : 1.0;
            seed(model, p, e.species, e.positionVoxels ? Eigen::Vector3d(*e.positionVoxels * h) : defaultSeedPosition(model, e.species), step);
        } else {
            setBirth(e.species, e.action == ConstructionEvent::Action::BirthOn);
        }
    }
    ConstructionCounts c;
    if (params_.everySteps <= 0 || step % params_.everySteps != 0) return c;
    if (std::find(birth_.begin(), birth_.end(), char(1)) == birth_.end()) return c;  // not building
    c.deaths = deaths(model, p, step);
    if (model.map)
        for (int s = 1; s < int(birth_.size()); ++s)
            if (birth_[std::size_t(s)]) c.births += births(model, p, s, step);
    totals_.births += c.births;
    totals_.deaths += c.deaths;
    return c;
}

std::size_t Construction::deaths(const Model& model, Particles& p, long long step) {
    const double d = params_.deathR0 * kR0;
    PointGrid grid;
    grid.build(model.box, d, p.pos);
    std::vector<char> marked(p.size(), 0);
    for (std::size_t i = 0; i < p.size(); ++i)
        grid.anyNear(p.pos[i], d, p.pos, [&](std::uint32_t j, double) {
            if (j <= i) return false;
            const bool si = model.isSurface(p.species[i]), sj = model.isSurface(p.species[j]);
            std::size_t victim;
            if (si != sj) victim = si ? j : i;  // surface + volume: the volume particle dies
            else victim = p.id[i] > p.id[j] ? i : j;
            marked[victim] = 1;
            return false;
        });
    // Cap per species, in hash order.
    std::vector<std::size_t> count(model.species.size(), 0);
    for (auto s : p.species) ++count[s];
    std::vector<std::pair<std::uint64_t, std::size_t>> order;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (marked[i]) order.emplace_back(mixHash(params_.seed, std::uint64_t(step), p.id[i]), i);
    std::sort(order.begin(), order.end());
    std::vector<std::size_t> killed(model.species.size(), 0);
    std::vector<char> die(p.size(), 0);
    std::size_t total = 0;
    for (const auto& [key, i] : order) {
        const int s = p.species[i];
        const std::size_t cap = std::max<std::size_t>(1, std::size_t(std::ceil(params_.capFraction * double(count[std::size_t(s)]))));
        if (killed[std::size_t(s)] >= cap) continue;
        ++killed[std::size_t(s)];
        die[i] = 1;
        ++total;
    }
    if (total) p.removeIf(die);
    return total;
}

std::size_t Construction::births(const Model& model, Particles& p, int species, long long step) {
    const GradientMap& m = *model.map;
    const double h = kR0 / m.r0Voxels;
    const double dSame = params_.sameR0 * kR0, dAny = params_.anyR0 * kR0, dFront = params_.frontR0 * kR0;
    // Blocked: a particle closer than dAny, or one of the species closer than dSame (a small
    // grid, and most voxels of a growing bag are blocked). Front: one of the species within dFront.
    const double dClose = std::max(dSame, dAny);
    PointGrid close, far;
    close.build(model.box, dClose, p.pos);
    far.build(model.box, dFront, p.pos);
    struct Candidate { Eigen::Vector3d pos; std::uint64_t key; std::size_t voxel; };
    std::vector<Candidate> accepted;
    std::size_t have = 0;
    for (auto s : p.species) have += s == species;
    if (have == 0) return 0;  // births grow from a seed
    for (std::size_t v = 0; v < m.occ.size(); ++v) {
        if (m.occ[v] != species) continue;
        const std::uint64_t key = mixHash(params_.seed, std::uint64_t(step), std::uint64_t(species), v);
        const Eigen::Vector3d jitter(unit(mixHash(key, 1)) - 0.5, unit(mixHash(key, 2)) - 0.5, unit(mixHash(key, 3)) - 0.5);
        const Eigen::Vector3d c = (m.dims().coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5) + 0.1 * jitter) * h;
        const bool blocked = close.anyNear(c, dClose, p.pos, [&](std::uint32_t j, double d2) {
            return d2 < dAny * dAny || (p.species[j] == species && d2 < dSame * dSame);
        });
        if (blocked) continue;
        const bool front = far.anyNear(c, dFront, p.pos, [&](std::uint32_t j, double) { return p.species[j] == species; });
        if (front) accepted.push_back({c, key, v});
    }
    // One priority round among candidates that conflict (closer than dSame): the smallest key wins.
    std::vector<Eigen::Vector3d> pts;
    for (const auto& a : accepted) pts.push_back(a.pos);
    PointGrid cand;
    cand.build(model.box, dSame, pts);
    std::vector<std::pair<std::uint64_t, std::size_t>> winners;
    for (std::size_t a = 0; a < accepted.size(); ++a) {
        bool keep = true;
        cand.anyNear(accepted[a].pos, dSame, pts, [&](std::uint32_t b, double) {
            if (b != a && accepted[b].key < accepted[a].key) keep = false;
            return !keep;
        });
        if (keep) winners.emplace_back(accepted[a].key, a);
    }
    std::sort(winners.begin(), winners.end());
    const std::size_t cap = std::max<std::size_t>(1, std::size_t(std::ceil(params_.capFraction * double(have))));
    if (winners.size() > cap) winners.resize(cap);
    for (const auto& [key, a] : winners) {
        const Candidate& c = accepted[a];
        const Eigen::Vector3d n = m.nearestSurface(c.voxel).normal.cast<double>();
        const std::uint64_t gid = (std::uint64_t(step + 1) << 32) | c.voxel;
        p.add(c.pos, species, gid, model.isSurface(species) ? orientationFor(n) : Eigen::Quaterniond::Identity());
    }
    return winners.size();
}

}  // namespace bop::core
