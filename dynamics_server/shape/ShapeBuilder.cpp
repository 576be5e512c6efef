#include "ShapeBuilder.hpp"

#include "BoundarySmoothing.hpp"
#include "Labels.hpp"
#include "bop/common/DistanceTransform.hpp"
#include "bop/common/GradientMapFile.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace bop::shape {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

void addTiming(std::vector<StageTiming>* t, const std::string& stage, double s, std::size_t items) {
    if (!t) return;
    for (auto& e : *t)
        if (e.stage == stage) {
            e.seconds += s;
            e.items += items;
            return;
        }
    t->push_back({stage, s, items});
}

// One line on what the boundary smoothing moved: voxels over all bags, the largest volume change.
std::string describeSmoothing(const ShapeSpec& spec, const std::vector<BoundarySmoothingReport>& reps) {
    std::size_t removed = 0, added = 0, kept = 0, worst = 0;
    double worstChange = 0;
    for (std::size_t b = 0; b < reps.size(); ++b) {
        removed += reps[b].removed;
        added += reps[b].added;
        kept += reps[b].keptForTopology;
        const double change =
            reps[b].voxelsBefore ? double(reps[b].voxelsAfter) / double(reps[b].voxelsBefore) - 1.0 : 0.0;
        if (std::abs(change) > std::abs(worstChange)) worstChange = change, worst = b;
    }
    std::ostringstream os;
    os.precision(2);
    os << "boundary smoothing: " << removed << " voxels out, " << added << " in, " << kept
       << " kept for topology or layout; largest volume change " << std::fixed << 100.0 * worstChange << "% ("
       << spec.bags[worst].name << ")";
    return os.str();
}

}  // namespace

VoxelGrid planGrid(const ShapeSpec& spec) {
    Eigen::AlignedBox3d box;
    for (const auto& bag : spec.bags)
        for (int f = 0; f < bag.source->frameCount(); ++f) box.extend(bag.source->boundsMm(f));
    VoxelGrid g;
    g.voxelMm = spec.grid.voxelMm;
    const Eigen::Vector3d extent = box.sizes() / g.voxelMm;
    if (spec.grid.size) {
        g.dims = *spec.grid.size;
        const Eigen::Vector3d n(g.dims.nx, g.dims.ny, g.dims.nz);
        g.originMm = box.center() - 0.5 * n * g.voxelMm;
        return g;
    }
    const int pad = spec.grid.paddingVoxels;
    Eigen::Vector3i n;
    for (int a = 0; a < 3; ++a) n[a] = int(std::ceil(extent[a] - 1e-9)) + 2 * pad;
    g.dims = {n.x(), n.y(), n.z()};
    // Keep the box centred; images stay aligned with their own voxels when extents are whole.
    g.originMm = box.min() - Eigen::Vector3d::Constant(pad * g.voxelMm) -
                 0.5 * (n.cast<double>() - 2.0 * pad * Eigen::Vector3d::Ones() - extent) * g.voxelMm;
    return g;
}

GradientMap buildGradientMap(const VoxelGrid& grid, const Volume<std::uint8_t>& depth, double r0Voxels,
                             const SurfaceGeometryParams& geometry, std::vector<StageTiming>* timings, int threads) {
    return buildGradientMap(grid, BagLayout::nested(depth), r0Voxels, geometry, timings, threads);
}

GradientMap buildGradientMap(const VoxelGrid& grid, const BagLayout& bags, double r0Voxels,
                             const SurfaceGeometryParams& geometry, std::vector<StageTiming>* timings, int threads) {
    const Dims& d = grid.dims;
    GradientMap map;
    map.grid = grid;
    map.r0Voxels = r0Voxels;
    map.bagCount = std::max(bags.count(), 1);
    map.bagParent = bags.parent;
    map.bagParent.resize(std::size_t(map.bagCount) + 1, 0);

    auto t0 = Clock::now();
    map.occ = labelVoxels(bags);
    std::vector<std::int32_t> feature(d.count(), kNoSite);
    for (std::size_t v = 0; v < d.count(); ++v) {
        if (!isSurfaceSpecies(map.occ[v])) continue;
        feature[v] = std::int32_t(map.surface.size());
        SurfaceVoxel sv;
        sv.voxel = std::uint32_t(v);
        sv.species = map.occ[v];
        map.surface.push_back(sv);
    }
    addTiming(timings, "label", since(t0), d.count());

    t0 = Clock::now();
    std::vector<std::int32_t> dist2;
    exactDistanceTransform(d, feature, dist2, threads);
    map.nearest.assign(feature.begin(), feature.end());
    addTiming(timings, "distance", since(t0), d.count());

    t0 = Clock::now();
    computeSurfaceGeometry(bags, geometry, map);
    addTiming(timings, "geometry", since(t0), map.surface.size());
    return map;
}

ShapeBuild buildShape(const ShapeSpec& spec, const ProgressFn& progress, int threads) {
    auto say = [&](const std::string& m) {
        if (progress) progress(m);
    };
    int frames = 1;
    for (const auto& bag : spec.bags) frames = std::max(frames, bag.source->frameCount());
    for (const auto& bag : spec.bags)
        if (bag.source->frameCount() != 1 && bag.source->frameCount() != frames)
            throw Error(spec.sceneFile, "key '" + bag.key + "': has " + std::to_string(bag.source->frameCount()) +
                                            " frames, others have " + std::to_string(frames) + "; expected 1 or " +
                                            std::to_string(frames));
    ShapeBuild out;
    const VoxelGrid grid = planGrid(spec);
    {
        std::ostringstream os;
        os << "grid " << grid.dims.nx << " x " << grid.dims.ny << " x " << grid.dims.nz << " voxels of " << grid.voxelMm
           << " mm (" << grid.dims.count() << " voxels), " << frames << " frame(s)";
        say(os.str());
    }
    for (int f = 0; f < frames; ++f) {
        auto t0 = Clock::now();
        std::vector<Mask> masks(spec.bags.size());
        for (std::size_t b = 0; b < spec.bags.size(); ++b) {
            const auto& src = *spec.bags[b].source;
            src.rasterize(src.frameCount() == 1 ? 0 : f, grid, masks[b]);
        }
        addTiming(&out.timings, "rasterize", since(t0), grid.dims.count() * spec.bags.size());
        const auto ts = Clock::now();
        std::vector<double> widths;
        for (const auto& bag : spec.bags) widths.push_back(bag.boundarySmoothingVoxels);
        const auto smoothed = smoothBoundaries(masks, widths, threads);
        if (std::any_of(widths.begin(), widths.end(), [](double w) { return w > 0; })) {
            addTiming(&out.timings, "smooth", since(ts), grid.dims.count() * spec.bags.size());
            say(describeSmoothing(spec, smoothed));
        }
        const BagLayout bags = arrangeBags(spec, masks, f);
        out.frames.push_back(buildGradientMap(grid, bags, spec.grid.r0Voxels, spec.geometry, &out.timings, threads));
        std::ostringstream os;
        os.precision(3);
        os << "frame " << f + 1 << "/" << frames << " done: " << out.frames.back().surface.size() << " surface voxels; "
           << std::fixed << since(t0) << " s (" << grid.dims.count() / std::max(since(t0), 1e-9) / 1e6 << " Mvoxel/s)";
        say(os.str());
    }
    return out;
}

ShapeBuild loadOrBuildShape(const ShapeSpec& spec, const std::string& cachePath, bool rebuild,
                            const ProgressFn& progress, int threads) {
    const std::uint64_t key = hashText(spec.canonical);
    if (!cachePath.empty() && !rebuild)
        if (auto cached = readGradientMaps(cachePath, key)) {
            if (progress) progress("read the gradient map from the cache " + cachePath);
            return ShapeBuild{std::move(*cached), {}};
        }
    ShapeBuild build = buildShape(spec, progress, threads);
    if (!cachePath.empty()) {
        writeGradientMaps(cachePath, build.frames, key);
        if (progress) progress("cached the gradient map in " + cachePath);
    }
    return build;
}

}  // namespace bop::shape
