#pragma once
// The shape part of a scene: the voxel grid and the nested bags with their model sources, read
// from the scene TOML's [grid] and [shape] tables (see config/scenes/*.toml for every key).
#include "BoundarySmoothing.hpp"
#include "ModelSource.hpp"
#include "SurfaceGeometry.hpp"
#include "bop/common/ConfigTable.hpp"
#include "bop/common/MapInterpolation.hpp"

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bop::shape {

struct GridSpec {
    double voxelMm = 0;        // voxel edge, mm; 0 = take it from the outer bag's image
    int paddingVoxels = 4;     // empty voxels between the objects' bounding box and the grid edge
    double r0Voxels = 2.0;     // LJ equilibrium spacing r0 in voxels (Table 1: 2 or 1.4)
    std::optional<Dims> size;  // fixed grid size in voxels, object centred (overrides padding)
};

struct BagSpec {
    std::string name;                            // shown in reports
    std::string key;                             // config key of this bag, for error messages
    std::shared_ptr<ModelSource> source;         // loaded and checked while reading the scene
    std::optional<std::array<float, 3>> colour;  // from a label table, r g b in [0, 1]
    // Gaussian width of the boundary's anti-aliasing, grid voxels; 0 = the voxels as rasterized
    // (shape/BoundarySmoothing.hpp). Images default to their coarsest spacing (one sample: the
    // slices' thickness) in grid voxels, at least 1; other sources to 0.
    double boundarySmoothingVoxels = 0;
};

// `boundary_smoothing_voxels` of a [[shape.bag]] table of source `kind`, checked; for an image
// without the key, kImageDefaultSmoothing until the grid's voxel size is known.
double readBoundarySmoothing(const ConfigTable& t, const std::string& kind);
inline constexpr double kImageDefaultSmoothing = -1.0;

struct ShapeSpec {
    std::string sceneFile;  // path of the scene file
    GridSpec grid;
    std::vector<BagSpec> bags;  // bag k = bags[k - 1], in the order the scene lists them
    SurfaceGeometryParams geometry;
    Interpolation interpolation = Interpolation::Mixed;
    std::string canonical;              // the shape tables as TOML text (for the cache key)
    std::vector<std::string> warnings;  // what the sources found and mended, one line each

    std::vector<std::string> bagNames() const {  // in bag order
        std::vector<std::string> names;
        for (const BagSpec& b : bags) names.push_back(b.name);
        return names;
    }
};

// Reads [grid] and [shape] of a scene (other top-level tables are left to their readers) and
// loads every model source; relative file names are taken from the scene file's folder.
// Throws bop::Error naming the file and key for every malformed input.
ShapeSpec readShapeSpec(const ConfigTable& root);

// Top-level scene tables that other readers own (the server's); shape-only tools accept them.
inline const std::vector<std::string> kOtherSceneTables = {"species", "interactions", "dynamics",  "construction",
                                                           "probe",   "run",          "keyframes", "pressure"};

// Convenience for tools that only need the shape: parse the file, read [grid]/[shape], and
// reject unknown top-level tables other than those listed in `otherTables`.
ShapeSpec loadShapeSpec(const std::string& sceneFile, const std::vector<std::string>& otherTables = kOtherSceneTables);

}  // namespace bop::shape
