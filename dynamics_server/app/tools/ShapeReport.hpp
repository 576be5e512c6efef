#pragma once
// What bop-shape tells and writes about built gradient maps: the text report, the .npy
// exports and the PNG slice pictures.
#include "shape/ShapeBuilder.hpp"

#include <ostream>
#include <set>
#include <string>

namespace bop::app {

// Grid size, voxel counts per label and species, distance and curvature statistics.
void printShapeReport(std::ostream& os, const shape::ShapeSpec& spec, const shape::ShapeBuild& build);

// Stage timings with time per voxel; optional CSV (stage,seconds,items,ns_per_item).
void printTimings(std::ostream& os, const std::vector<shape::StageTiming>& timings);
void writeTimingsCsv(const std::string& path, const GradientMap& map, const std::vector<shape::StageTiming>& timings);

// Arrays in NumPy layout (nz, ny, nx[, 3]); `what` from {labels, species, vectors,
// distance, normals, curvature, weight}. Files go to dir (per frame: dir/frameNN/ if several).
void exportNpy(const std::string& dir, const shape::ShapeBuild& build, const std::set<std::string>& what);
extern const std::set<std::string> kNpyArrays;

// Three orthogonal slices through the grid centre per frame: labels, signed distance and
// co-planar weight, with legends. Returns the files written.
std::vector<std::string> writeSlicePictures(const std::string& dir, const shape::ShapeBuild& build);

}  // namespace bop::app
