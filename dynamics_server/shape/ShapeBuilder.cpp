#include "ShapeBuilder.hpp"

#include "DistanceTransform.hpp"
#include "Labels.hpp"
#include "bop/common/GradientMapFile.hpp"

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

Volume<std::uint8_t> nestBags(const ShapeSpec& spec, const std::vector<Mask>& masks, int frame) {
    const Dims d = masks.front().dims;
    Volume<std::uint8_t> depth(d, 0);
    const std::string at = spec.bags.size() > 1 || frame > 0 ? " (frame " + std::to_string(frame) + ")" : "";
    for (std::size_t b = 0; b < masks.size(); ++b) {
        std::size_t count = 0, stray = 0;
        for (std::size_t v = 0; v < d.count(); ++v) {
            if (!masks[b].data[v]) continue;
            ++count;
            if (depth.data[v] != b)
                ++stray;  // not inside every outer bag
            else
                depth.data[v] = std::uint8_t(b + 1);
        }
        const std::string where = spec.sceneFile;
        if (count == 0)
            throw Error(where, "key '" + spec.bags[b].key + "': bag '" + spec.bags[b].name + "' (" +
                                   spec.bags[b].source->describe() + ") has no object voxels on the grid" + at +
                                   "; expected a non-empty bitmap (check its size against voxel_size_mm)");
        if (stray)
            throw Error(where, "key '" + spec.bags[b].key + "': " + std::to_string(stray) + " voxels of bag '" +
                                   spec.bags[b].name + "' lie outside bag '" + spec.bags[b - 1].name + "'" + at +
                                   "; nested bags must be listed outer to inner, each inside the previous");
    }
    for (std::size_t b = 1; b < masks.size(); ++b) {
        std::size_t touching = 0;
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i)
                    if (depth(i, j, k) == b + 1 && touchesBelow(depth, i, j, k, int(b))) ++touching;
        if (touching)
            throw Error(spec.sceneFile, "key '" + spec.bags[b].key + "': bag '" + spec.bags[b].name +
                                            "' touches the outside of bag '" + spec.bags[b - 1].name + "' at " +
                                            std::to_string(touching) + " voxels" + at +
                                            "; an inner bag must lie strictly inside the outer bag's surface");
    }
    return depth;
}

GradientMap buildGradientMap(const VoxelGrid& grid, const Volume<std::uint8_t>& depth, double r0Voxels,
                             const SurfaceGeometryParams& geometry, std::vector<StageTiming>* timings, int threads) {
    const Dims& d = grid.dims;
    GradientMap map;
    map.grid = grid;
    map.r0Voxels = r0Voxels;
    int bags = 0;
    for (auto x : depth.data) bags = std::max(bags, int(x));
    map.bagCount = std::max(bags, 1);

    auto t0 = Clock::now();
    map.occ = labelVoxels(depth);
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
    computeSurfaceGeometry(depth, geometry, map);
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
        const Volume<std::uint8_t> depth = nestBags(spec, masks, f);
        const double tr = since(t0);
        addTiming(&out.timings, "rasterize", tr, grid.dims.count() * spec.bags.size());
        out.frames.push_back(buildGradientMap(grid, depth, spec.grid.r0Voxels, spec.geometry, &out.timings, threads));
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
