#include "core/MapField.hpp"

#include <algorithm>
#include <cmath>

namespace bop::core {

MapField::MapField(const GradientMap& map, Interpolation interp)
    : map_(map), interp_(interp), h_(voxelLength(map.r0Voxels)) {
    surfaceAt_.reserve(map.surface.size());
    for (const SurfaceVoxel& s : map.surface) surfaceAt_.push_back(map.wholeDims().coords(s.voxel));
}

Eigen::Vector3d MapField::normalAtVoxel(std::size_t v) const {
    return map_.nearestSurface(v).normal.cast<double>();
}

Eigen::Vector3d MapField::ruleAtVoxel(std::size_t v, ParticleKind kind, int species,
                                      const Eigen::Vector3d& pVox) const {
    return rule(v, map_.dims().coords(v), kind, species, pVox);
}

Eigen::Vector3d MapField::rule(std::size_t v, const Eigen::Vector3i& c, ParticleKind kind, int species,
                               const Eigen::Vector3d& pVox) const {
    const int o = map_.occ[v];
    if (o == species) {  // at home: no look-up of the nearest surface (most volume particles, every step)
        if (kind == ParticleKind::Surface) return c.cast<double>() + Eigen::Vector3d::Constant(0.5) - pVox;
        return Eigen::Vector3d::Zero();
    }
    const std::uint32_t k = map_.nearest[v];
    const SurfaceVoxel& near = map_.surface[k];
    const int sigma = near.species;
    // d(v) of GradientMap::delta, from the surface voxel's coordinates kept at construction.
    const Eigen::Vector3d d = (surfaceAt_[k] - c - map_.origin).cast<double>();
    // The bags of the voxel (0: outside every bag), of the nearest surface and of the particle.
    const int bagO = bagOfSpecies(o), bagS = bagOfSpecies(sigma), bagP = bagOfSpecies(species);
    // Direction "inward with respect to the nearest surface" (docs/physics.md §4.6).
    auto inward = [&]() -> Eigen::Vector3d {
        if (o == sigma) return -near.normal.cast<double>();
        return map_.bagWithin(bagO, bagS) ? -d : d;
    };
    if (!map_.bagWithin(bagP, bagS) && !map_.bagWithin(bagS, bagP)) {
        // The nearest surface is another object's (side by side or touching): out of it, never
        // towards it; outside every bag, nothing (its own bag lies beyond the map's knowledge here).
        if (bagO == 0) return Eigen::Vector3d::Zero();
        return -inward();
    }
    if (kind == ParticleKind::Surface) {
        if (sigma == surfaceSpeciesOfBag(bagP)) return d;
        if (map_.bagWithin(bagP, bagS)) return inward();  // its surface lies inside the nearest one
        return -inward();
    }
    if (bagO != bagP && map_.bagWithin(bagO, bagP)) return -inward();  // in a bag inside its own
    return inward();
}

MapSample MapField::sample(ParticleKind kind, int species, const Eigen::Vector3d& position,
                           const Eigen::Vector3d& normal, Memo* memo) const {
    const Dims& dm = map_.dims();
    const Dims& whole = map_.wholeDims();
    const Eigen::Vector3d pWhole = position / h_;
    if (kind == ParticleKind::Volume && interp_ != Interpolation::Nearest) {
        // Most of a bag's particles: a volume particle amid voxels of its own species, away from
        // the grid's edges, feels nothing. Found from 8 bytes of the map before anything else is
        // computed (the general path below gives the same zero).
        const Eigen::Vector3d s = pWhole - map_.origin.cast<double>() - Eigen::Vector3d::Constant(0.5);
        const bool interior = s.x() >= 0 && s.y() >= 0 && s.z() >= 0 && s.x() < dm.nx - 1 && s.y() < dm.ny - 1 &&
                              s.z() < dm.nz - 1 && pWhole.x() >= 0.5 && pWhole.y() >= 0.5 && pWhole.z() >= 0.5 &&
                              pWhole.x() <= whole.nx - 0.5 && pWhole.y() <= whole.ny - 0.5 &&
                              pWhole.z() <= whole.nz - 0.5;
        if (interior) {
            const std::size_t v = dm.index(int(s.x()), int(s.y()), int(s.z()));  // floor: s >= 0
            const std::size_t dy = std::size_t(dm.nx), dz = std::size_t(dm.nx) * std::size_t(dm.ny);
            const std::uint8_t* o = map_.occ.data() + v;
            const auto home = [&](std::size_t k) { return o[k] == species && o[k + 1] == species; };
            if (home(0) && home(dy) && home(dz) && home(dy + dz)) return MapSample{};
        }
    }
    // Keep the evaluation point on the grid; a particle beyond the whole map's grid is pulled
    // back by a spring. A crop's margin keeps its particles inside it (bop/common/GradientMapCrop.hpp).
    const Eigen::Vector3d wholeHi(whole.nx - 0.5, whole.ny - 0.5, whole.nz - 0.5);
    const Eigen::Vector3d back = pWhole.cwiseMax(Eigen::Vector3d::Constant(0.5)).cwiseMin(wholeHi) - pWhole;
    const Eigen::Vector3d pVox = pWhole - map_.origin.cast<double>();  // this map's voxel coordinates
    const Eigen::Vector3d hi(dm.nx - 0.5, dm.ny - 0.5, dm.nz - 0.5);
    const Eigen::Vector3d q = pVox.cwiseMax(Eigen::Vector3d::Constant(0.5)).cwiseMin(hi);

    Eigen::Vector3d f = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
    float cpWeight = 1.0f;
    const bool nearest =
        interp_ == Interpolation::Nearest || (interp_ == Interpolation::Mixed && kind == ParticleKind::Surface);
    if (nearest) {
        const Eigen::Vector3i c =
            q.array().floor().cast<int>().min(Eigen::Array3i(dm.nx - 1, dm.ny - 1, dm.nz - 1)).matrix();
        const std::size_t v = dm.index(c.x(), c.y(), c.z());
        f = rule(v, c, kind, species, q);
        Memo once;  // without a caller's memo, read afresh
        Memo& m = memo ? *memo : once;
        if (m.voxel != v) {  // the particle moved to another voxel, or no memo yet
            const SurfaceVoxel& s = map_.nearestSurface(v);
            m = {v, s.normal, s.cpWeight};
        }
        n = m.normal.cast<double>();
        cpWeight = m.cpWeight;
    } else {
        const Eigen::Vector3d s = q - Eigen::Vector3d::Constant(0.5);  // centre-based coordinates
        Eigen::Vector3i base = s.array().floor().cast<int>().matrix();
        base = base.cwiseMin(Eigen::Vector3i(dm.nx - 2, dm.ny - 2, dm.nz - 2)).cwiseMax(Eigen::Vector3i::Zero());
        const Eigen::Vector3d t =
            (s - base.cast<double>()).cwiseMax(Eigen::Vector3d::Zero()).cwiseMin(Eigen::Vector3d::Ones());
        // The 8 voxels around the particle; a volume particle whose species fills all of them
        // (most of a bag's volume) feels no force from them: rule() would give zeros.
        std::size_t at[8];
        const int hi1[3] = {std::min(base.x() + 1, dm.nx - 1), std::min(base.y() + 1, dm.ny - 1),
                            std::min(base.z() + 1, dm.nz - 1)};
        bool home = kind == ParticleKind::Volume;
        for (int corner = 0; corner < 8; ++corner) {
            at[corner] = dm.index(corner & 1 ? hi1[0] : base.x(), corner & 2 ? hi1[1] : base.y(),
                                  corner & 4 ? hi1[2] : base.z());
            home = home && map_.occ[at[corner]] == species;
        }
        for (int corner = 0; corner < 8 && !home; ++corner) {
            const int a = corner & 1, b = (corner >> 1) & 1, c = (corner >> 2) & 1;
            const double w = (a ? t.x() : 1 - t.x()) * (b ? t.y() : 1 - t.y()) * (c ? t.z() : 1 - t.z());
            if (w == 0.0) continue;
            const Eigen::Vector3i xyz(a ? hi1[0] : base.x(), b ? hi1[1] : base.y(), c ? hi1[2] : base.z());
            f += w * rule(at[corner], xyz, kind, species, q);
            if (kind == ParticleKind::Surface) n += w * normalAtVoxel(at[corner]);
        }
        if (kind == ParticleKind::Surface) {
            const double len = n.norm();
            if (len > 1e-6)
                n /= len;
            else {
                n = normalAtVoxel(floorVoxel(q));
            }
            cpWeight = map_.nearestSurface(floorVoxel(q)).cpWeight;
        }
    }
    MapSample out;
    out.force = (f + back) * h_;
    if (kind == ParticleKind::Surface) {
        out.torque = normal.cross(n);
        out.cpWeight = cpWeight;
    }
    return out;
}

}  // namespace bop::core
