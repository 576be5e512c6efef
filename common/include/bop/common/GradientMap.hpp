#pragma once
// The labelled gradient map of one shape (paper §3.3–3.5, docs/physics.md §4): per voxel the species
// that should occupy it and its nearest surface voxel; per surface voxel its species, outward
// normal, curvature and co-planar weight. Built by dynamics_server/shape, read by the dynamics
// core and the haptic client. Lengths are in voxels unless a name says otherwise.
#include "bop/common/Volume.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

namespace bop {

// Species numbering (paper §3.4): bag k = 1, 2, ... (in the order the scene lists them) has
// surface species 2k-1 and volume species 2k; species 0 is "outside every bag". Bags form a forest
// of containment (GradientMap::bagParent): side by side, touching, or nested in any of them.
inline int surfaceSpeciesOfBag(int bag) {
    return 2 * bag - 1;
}
inline int volumeSpeciesOfBag(int bag) {
    return 2 * bag;
}
inline bool isSurfaceSpecies(int species) {
    return species % 2 == 1;
}
inline int bagOfSpecies(int species) {  // 0 for "outside every bag"
    return (species + 1) / 2;
}
inline constexpr int kMaxBags = 127;  // species numbers fit a byte

// The bag holding `bag` directly (0: none), parent[b] giving it for bag b; a bag beyond `parent`
// continues the paper's chain of nested bags (bag b inside bag b - 1).
inline int parentOfBag(std::span<const std::uint8_t> parent, int bag) {
    return std::size_t(bag) < parent.size() ? int(parent[std::size_t(bag)]) : bag - 1;
}
// Whether bag a is bag b or lies inside it (bag 0, outside every bag, lies in none).
inline bool bagWithin(std::span<const std::uint8_t> parent, int a, int b) {
    for (int steps = 0; a > 0 && steps <= 2 * kMaxBags; ++steps, a = parentOfBag(parent, a))
        if (a == b) return true;
    return false;
}

struct SurfaceVoxel {
    std::uint32_t voxel = 0;          // linear voxel index in the whole map (wholeDims().index)
    std::uint8_t species = 0;         // surface species of this voxel (odd)
    Eigen::Vector3f normal{0, 0, 1};  // outward unit normal of the smoothed surface
    float meanCurvature = 0;          // H, 1/voxel (> 0 on convex parts)
    float gaussCurvature = 0;         // K, 1/voxel^2
    float kappa = 0;                  // max |principal curvature|, 1/voxel
    float cpWeight = 1;               // co-planar weight w in (0, 1] (docs/physics.md §5.3), dimensionless
};

struct GradientMap {
    VoxelGrid grid;         // placement in model space (mm)
    double r0Voxels = 2.0;  // LJ equilibrium spacing r0, in voxels
    int bagCount = 1;       // bags (each a surface and a volume species)
    // bagParent[b]: the bag that holds bag b directly (0: none), b = 1..bagCount, [0] unused.
    // Empty: the paper's chain of nested bags, each inside the one before (bag b in bag b - 1).
    std::vector<std::uint8_t> bagParent;
    std::vector<std::uint8_t> occ;       // species that should occupy each voxel (0 = outside)
    std::vector<std::uint32_t> nearest;  // per voxel: index into `surface` of the nearest surface voxel
    std::vector<SurfaceVoxel> surface;   // every surface voxel the voxels name, in voxel-index order
    // A window of a larger map (one rank's subdomain plus a margin, bop/common/GradientMapCrop.hpp):
    // voxel (0,0,0) of this map is voxel `origin` of the whole map, of size `whole`. A whole
    // map has origin 0 and `whole` empty. grid.originMm stays the whole map's.
    Eigen::Vector3i origin = Eigen::Vector3i::Zero();
    Dims whole;

    const Dims& dims() const { return grid.dims; }
    const Dims& wholeDims() const { return whole.count() ? whole : grid.dims; }
    const SurfaceVoxel& nearestSurface(std::size_t v) const { return surface[nearest[v]]; }
    // Coordinates and linear index of voxel v in the whole map.
    Eigen::Vector3i wholeCoords(std::size_t v) const { return dims().coords(v) + origin; }
    std::uint64_t wholeIndex(std::size_t v) const {
        const Eigen::Vector3i c = wholeCoords(v);
        return wholeDims().index(c.x(), c.y(), c.z());
    }
    // This map's voxel at whole-map coordinates c, clamped into this map.
    std::size_t voxelAt(const Eigen::Vector3i& c) const {
        const Dims& d = dims();
        const Eigen::Vector3i l = (c - origin).cwiseMax(0).cwiseMin(Eigen::Vector3i(d.nx - 1, d.ny - 1, d.nz - 1));
        return d.index(l.x(), l.y(), l.z());
    }

    // This map's voxel holding the point x (whole-map voxel coordinates), or -1 when x lies
    // outside this map (its window).
    std::int64_t voxelHolding(const Eigen::Vector3d& x) const {
        const Eigen::Vector3i c =
            Eigen::Vector3i(int(std::floor(x.x())), int(std::floor(x.y())), int(std::floor(x.z()))) - origin;
        return dims().contains(c.x(), c.y(), c.z()) ? std::int64_t(dims().index(c.x(), c.y(), c.z())) : -1;
    }

    // d(v): vector from the centre of v to the centre of its nearest surface voxel, voxels.
    Eigen::Vector3i delta(std::size_t v) const { return wholeDims().coords(nearestSurface(v).voxel) - wholeCoords(v); }
    // Species of the nearest surface (paper §3.4 "species of the nearest surface").
    int nearestSpecies(std::size_t v) const { return nearestSurface(v).species; }
    // Signed distance to the nearest surface voxel centre: + outside its bag, - inside, voxels.
    double signedDistance(std::size_t v) const {
        const double d = delta(v).cast<double>().norm();
        return inBag(v, bagOfSpecies(nearestSpecies(v))) ? -d : d;
    }

    // A bag beyond the map's (a species the model has and the map does not) continues the chain.
    int parentBag(int bag) const { return parentOfBag(bagParent, bag); }
    bool bagWithin(int a, int b) const { return bop::bagWithin(bagParent, a, b); }
    // Whether voxel v belongs to bag b or to a bag inside it.
    bool inBag(std::size_t v, int b) const { return bagWithin(bagOfSpecies(occ[v]), b); }
};

}  // namespace bop
