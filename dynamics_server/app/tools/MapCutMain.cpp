// bop-map-cut: what the map edit of a cut costs (scripts/bench/cut.sh, docs/shape-pipeline.md "Map
// edits"). Sweeps blades of a stated radius along strokes of several lengths into a scene's bags,
// one after another as a session would, and times each windowed edit on one core: the patch
// (bop::cutPatch: labels, exact distances, surface records in its window) and its application to
// the whole map; with --check, the edited map against a whole-grid rebuild of the edited image.
// One CSV row per stroke.
#include "app/scene/SceneConfig.hpp"
#include "bop/common/GradientMapCrop.hpp"
#include "bop/common/GradientMapEdit.hpp"
#include "bop/common/ToolMain.hpp"
#include "shape/ShapeBuilder.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The map as the image it was built from: each voxel in its innermost bag.
bop::shape::BagLayout layoutOf(const bop::GradientMap& m) {
    bop::shape::BagLayout l;
    l.bag = bop::Volume<std::uint8_t>(m.dims(), 0);
    for (std::size_t v = 0; v < m.occ.size(); ++v) l.bag.data[v] = std::uint8_t(bop::bagOfSpecies(m.occ[v]));
    l.parent = m.bagParent;
    return l;
}

bool sameMap(const bop::GradientMap& a, const bop::GradientMap& b) {
    if (a.occ != b.occ || a.surface.size() != b.surface.size()) return false;
    for (std::size_t v = 0; v < a.occ.size(); ++v)
        if (a.delta(v).squaredNorm() != b.delta(v).squaredNorm()) return false;
    for (std::size_t s = 0; s < a.surface.size(); ++s) {
        const bop::SurfaceVoxel &x = a.surface[s], &y = b.surface[s];
        if (x.voxel != y.voxel || x.species != y.species || x.normal != y.normal || x.kappa != y.kappa ||
            x.cpWeight != y.cpWeight)
            return false;
    }
    return true;
}

int run(int argc, char** argv) {
    CLI::App app{
        "bop-map-cut: time the windowed map edits of cuts into a scene's bags on one core, one CSV row a "
        "stroke (scripts/bench/cut.sh)"};
    std::string scene, cache, csvPath = "map-cut.csv";
    double radiusR0 = 1;
    int strokes = 24;
    bool check = false;
    app.add_option("scene", scene, "scene file (TOML)")->required();
    app.add_option("--cache", cache, "gradient-map cache file (default: none, the map is built)");
    app.add_option("--radius", radiusR0, "the blade's radius, r0")->check(CLI::Range(0.25, 8.0));
    app.add_option("--strokes", strokes, "strokes, each a blade swept 0 to 5 r0 into a bag")
        ->check(CLI::Range(1, 10000));
    app.add_option("--csv", csvPath, "the table, one row per stroke");
    app.add_flag("--check", check, "compare every edited map with a whole-grid rebuild of the edited image");
    CLI11_PARSE(app, argc, argv);

    const bop::app::Scene s = bop::app::loadScene(scene);
    if (!s.shape) throw bop::Error(scene, "a scene with a shape ([[shape.bag]]) is needed: bulk material has no map");
    bop::GradientMap map = bop::shape::loadOrBuildShape(*s.shape, cache).frames.front();
    const double r = radiusR0 * map.r0Voxels;
    std::vector<std::uint32_t> surface;
    for (const bop::SurfaceVoxel& sv : map.surface) surface.push_back(sv.voxel);
    std::printf("bop-map-cut: %s, grid %d x %d x %d voxels, %zu surface voxels; blade radius %.2f voxels (%.2f r0)\n",
                scene.c_str(), map.dims().nx, map.dims().ny, map.dims().nz, surface.size(), r, radiusR0);
    std::ofstream csv(csvPath);
    csv << "stroke,length_voxels,window_x,window_y,window_z,window_voxels,removed,new_surface,grows,patch_ms,apply_"
           "whole_ms,rebuild_ms,equal\n";
    std::mt19937 rng(52);
    std::size_t equal = 0;
    for (int k = 0; k < strokes; ++k) {
        // From a surface voxel into the bag, along the inward normal, 0 to 5 r0 long.
        const bop::SurfaceVoxel& at =
            *std::lower_bound(map.surface.begin(), map.surface.end(), surface[rng() % surface.size()],
                              [](const bop::SurfaceVoxel& a, std::uint32_t v) { return a.voxel < v; });
        bop::BladeSweep blade;
        blade.a = map.dims().coords(at.voxel).cast<double>() + Eigen::Vector3d::Constant(0.5);
        const double length = (k % 6) * map.r0Voxels;
        blade.b = blade.a - length * at.normal.cast<double>();
        blade.radius = r;
        auto t0 = Clock::now();
        const bop::MapPatch patch =
            bop::cutPatch([&](const bop::VoxelWindow& w) { return bop::cropGradientMap(map, w); }, map.dims(),
                          map.r0Voxels, blade, s.model->mapGeometry);
        const double patchMs = msSince(t0);
        if (patch.empty()) continue;
        t0 = Clock::now();
        map = bop::applyPatch(map, patch);
        const double applyMs = msSince(t0);
        double rebuildMs = 0;
        bool same = true;
        if (check) {
            t0 = Clock::now();
            const bop::GradientMap truth =
                bop::shape::buildGradientMap(map.grid, layoutOf(map), map.r0Voxels, s.model->mapGeometry, nullptr, 1);
            rebuildMs = msSince(t0);
            same = sameMap(map, truth);
        }
        equal += same;
        const bop::Dims w = patch.window.dims();
        csv << k << ',' << length << ',' << w.nx << ',' << w.ny << ',' << w.nz << ',' << w.count() << ','
            << patch.removed << ',' << patch.newSurface << ',' << patch.grows << ',' << patchMs << ',' << applyMs << ','
            << rebuildMs << ',' << (check ? (same ? "yes" : "no") : "") << '\n';
        std::printf(
            "stroke %d: %.1f voxels long, window %d x %d x %d, %zu voxels out, %zu new surface; patch %.2f ms, "
            "applied to the whole map %.2f ms%s\n",
            k, length, w.nx, w.ny, w.nz, patch.removed, patch.newSurface, patchMs, applyMs,
            check ? (same ? ", equal to a whole-grid rebuild" : ", DIFFERS from a whole-grid rebuild") : "");
        std::fflush(stdout);
    }
    std::printf("bop-map-cut: table in %s%s\n", csvPath.c_str(), check ? "" : " (no --check)");
    return check && equal == 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-map-cut", [&] { return run(argc, argv); });
}
