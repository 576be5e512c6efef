#pragma once
// Building a bag by placement (docs/physics.md §7.5), beside the paper's birth and death, once at
// the run's start (RunStart.hpp): every
// species' particles are set directly on its voxels of the whole gradient map at r0 spacing, and
// the run's damped dynamics relaxes them.
//  - A surface species gets a sheet: its voxels' centres, each moved by a hashed jitter, taken in
//    hash order when no taken one lies within a spacing d (random sequential adsorption). d is
//    bisected so that the count matches a hexagonal sheet at r0 over the species' surface area,
//    A = sum over the shell's outer voxel faces of h^2 / |n|_1 (n: the map's normal; exact for a
//    plane, where a unit of area shows |n_x| + |n_y| + |n_z| faces), or h^2 for a face amid a
//    flat patch of faces (3 x 3), where the smoothed normal tilts near a sharp edge.
//    SheetArea::MidShell counts the sheet where the map holds it instead, at the shell voxels'
//    centres half a voxel beneath the faces: A = half the sum over the shell's outer and inner
//    faces (those on the bag's volume or a bag inside it), each weighted so. On a ball of radius R
//    voxels that is 4 pi (R - 1/2)^2, (1 - 1/(2R))^2 of the faces' area: a small or thin part's
//    sheet is not crowded out of its voxels, at a count below the object's own area.
//    Where the bag is a membrane (PlacementParams::membrane: thinner than 2 r0), the outer faces
//    on both sides hold one sheet between them, and each counts half.
//  - A volume species gets an fcc lattice at nearest-neighbour distance r0, the sites that fall
//    in its voxels and lie at least `gapR0` from every surface particle; of 8 hashed shifts of
//    the lattice, the one with the most such sites.
// Every connected piece of every species is filled (there are no seeds to grow from). Ids count
// from 1 in placement order. Deterministic: the same map, parameters and seed give the same
// particles on every process, in the same order.
#include "core/Model.hpp"
#include "core/Particles.hpp"

#include <cstdint>
#include <vector>

namespace bop::app {

enum class SheetArea { Faces, MidShell };

struct PlacementParams {
    double gapR0 = 0.5;                      // least distance from a volume site to a surface particle, r0 (death_r0)
    SheetArea sheetArea = SheetArea::Faces;  // the area a sheet's count is taken over
    std::uint64_t seed = 1;                  // jitter, order and lattice offset
    // Per voxel of the map, 1 where its bag is thinner than 2 r0 (shape::thinPartsWarnings): there
    // the outer faces on both sides hold one sheet between them, a membrane, and each counts half.
    // Null: every part counts its faces whole.
    const std::vector<char>* membrane = nullptr;
    // The sheet's jitter along the surface only (its component along the map's normal dropped): a
    // bonded bag (docs/physics.md §8.3) keeps its placed sheet as its rest shape, and a face stays
    // as flat as its voxels' centres.
    bool flatSheet = false;
};

struct PlacedSpecies {
    int species = 0;
    std::size_t placed = 0;   // particles set
    double ideal = 0;         // the count at r0 spacing: hexagonal sheet over the area, fcc over the volume
    double areaOrVolume = 0;  // surface: area, length^2; volume: voxel volume, length^3 (simulation units)
};

struct Placement {
    core::Particles particles;
    std::vector<PlacedSpecies> species;  // every species with voxels, by number
};

// `map` must be the whole map (window origin 0, every voxel); std::invalid_argument if it is a
// window.
Placement placeParticles(const core::Model& model, const GradientMap& map, const PlacementParams& params);

}  // namespace bop::app
