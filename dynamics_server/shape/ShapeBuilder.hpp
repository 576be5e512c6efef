#pragma once
// From a shape spec to gradient maps: plan the grid, rasterize each bag, lay the bags out (side by
// side, touching, nested), label, run the exact distance transform, and compute normals,
// curvature and co-planar weights.
#include "BagLayout.hpp"
#include "ShapeSpec.hpp"
#include "bop/common/GradientMap.hpp"

#include <functional>
#include <string>
#include <vector>

namespace bop::shape {

struct StageTiming {
    std::string stage;      // "rasterize", "smooth", "label", "distance", "geometry"
    double seconds = 0;     // wall time, s
    std::size_t items = 0;  // voxels (or surface voxels for "geometry") processed
};

struct ShapeBuild {
    std::vector<GradientMap> frames;   // one map per time frame, all on one grid
    std::vector<StageTiming> timings;  // summed over frames
};

using ProgressFn = std::function<void(const std::string& message)>;

// The grid that holds every bag of every frame, with the spec's padding or fixed size.
VoxelGrid planGrid(const ShapeSpec& spec);

// Labels, exact distance transform and surface geometry for one layout of bags.
GradientMap buildGradientMap(const VoxelGrid& grid, const BagLayout& bags, double r0Voxels,
                             const SurfaceGeometryParams& geometry, std::vector<StageTiming>* timings = nullptr,
                             int threads = 0);
// The same for the paper's nested bags: depth(v) = number of bags holding v.
GradientMap buildGradientMap(const VoxelGrid& grid, const Volume<std::uint8_t>& depth, double r0Voxels,
                             const SurfaceGeometryParams& geometry, std::vector<StageTiming>* timings = nullptr,
                             int threads = 0);

ShapeBuild buildShape(const ShapeSpec& spec, const ProgressFn& progress = {}, int threads = 0);

// The maps from the cache file when it was made for this spec (and rebuild is false), else
// built and written to it. cachePath "" = no cache. Timings are empty for maps from the cache.
ShapeBuild loadOrBuildShape(const ShapeSpec& spec, const std::string& cachePath, bool rebuild = false,
                            const ProgressFn& progress = {}, int threads = 0);

}  // namespace bop::shape
