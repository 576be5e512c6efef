#pragma once
// What bop-shape tells and writes about built gradient maps: the text report, the .npy
// exports and the PNG slice pictures.
#include "shape/ShapeBuilder.hpp"

#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace bop::app {

// Grid size, voxel counts per label and species, distance and curvature statistics.
void printShapeReport(std::ostream& os, const shape::ShapeSpec& spec, const shape::ShapeBuild& build);

// One bag of a map: its voxels, the bag holding it directly (0: none) and the bags it touches
// (neither inside the other) with the voxel faces each pair shares.
struct BagSummary {
    int bag = 0;
    std::string name;
    std::size_t surfaceVoxels = 0, volumeVoxels = 0;
    double volumeMl = 0;  // its own voxels (not those of bags inside it), mL
    int parent = 0;
    std::vector<std::pair<int, std::size_t>> touching;  // (bag, shared faces), by bag number
};
std::vector<BagSummary> summariseBags(const GradientMap& map, const std::vector<std::string>& names);
// One line per bag; and the same as CSV (bag, name, voxels, volume, inside_bag, touching_bags and
// shared_faces as space-separated lists).
void printBagReport(std::ostream& os, const std::vector<BagSummary>& bags);
void writeBagsCsv(const std::string& path, const std::vector<BagSummary>& bags);

// Stage timings with time per voxel; optional CSV (stage,seconds,items,ns_per_item).
void printTimings(std::ostream& os, const std::vector<shape::StageTiming>& timings);
void writeTimingsCsv(const std::string& path, const GradientMap& map, const std::vector<shape::StageTiming>& timings);

// Arrays in NumPy layout (nz, ny, nx[, 3]); `what` from {labels, species, vectors,
// distance, normals, curvature, weight}. Files go to dir (per frame: dir/frameNN/ if several).
void exportNpy(const std::string& dir, const shape::ShapeBuild& build, const std::set<std::string>& what);
extern const std::set<std::string> kNpyArrays;

// Three orthogonal slices through the grid centre per frame: labels, signed distance and
// co-planar weight, with legends naming each species' bag. Returns the files written.
std::vector<std::string> writeSlicePictures(const std::string& dir, const shape::ShapeBuild& build,
                                            const std::vector<std::string>& bagNames);

}  // namespace bop::app
