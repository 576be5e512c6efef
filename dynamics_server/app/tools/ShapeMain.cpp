// bop-shape SCENE.toml: builds the scene's gradient map(s), prints what it built and how long
// each stage took, writes PNG slices and .npy arrays, and caches the map for the server.
#include "app/tools/ShapeReport.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/ToolMain.hpp"
#include "shape/ShapeBuilder.hpp"
#include "shape/Thickness.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;

namespace {

std::set<std::string> parseExports(const std::string& list) {
    std::set<std::string> out;
    if (list == "none") return out;
    if (list == "all") return bop::app::kNpyArrays;
    std::stringstream ss(list);
    for (std::string item; std::getline(ss, item, ',');) {
        if (!bop::app::kNpyArrays.count(item)) {
            std::string known;
            for (const auto& k : bop::app::kNpyArrays) known += " " + k;
            throw bop::Error("--export",
                             "unknown array '" + item + "' (expected all, none or a list of:" + known + ")");
        }
        out.insert(item);
    }
    return out;
}

int run(int argc, char** argv) {
    CLI::App app{
        "bop-shape: build and inspect the gradient map of a BoP scene (labels, exact distance "
        "vectors, normals, curvature), write PNG slices and .npy arrays, and cache the map."};
    std::string scene, outDir, cache, exports = "labels,species,vectors", timingsCsv;
    bool noPng = false, rebuild = false, noCache = false;
    int threads = 0;
    app.add_option("scene", scene, "scene file (TOML) with [grid] and [shape] tables")->required();
    app.add_option("-o,--out", outDir, "output folder (default: out/<scene name>)");
    app.add_option("--cache", cache, "gradient-map cache file (default: <out>/gradient-map.bopgm)");
    app.add_flag("--no-cache", noCache, "neither read nor write the cache");
    app.add_flag("--rebuild", rebuild, "build even if the cache matches the scene");
    app.add_option("--export", exports,
                   "arrays to write as .npy: all, none, or a comma list of "
                   "labels,species,vectors,distance,normals,curvature,weight")
        ->capture_default_str();
    app.add_flag("--no-png", noPng, "do not write slice pictures");
    app.add_option("--threads", threads, "OpenMP threads for the distance transform (0 = all cores)");
    app.add_option("--timings-csv", timingsCsv, "append-free CSV of stage timings (for benchmarks)");
    CLI11_PARSE(app, argc, argv);

    const std::set<std::string> what = parseExports(exports);
    if (outDir.empty()) outDir = "out/" + fs::path(scene).stem().string();
    if (cache.empty()) cache = outDir + "/gradient-map.bopgm";
    fs::create_directories(outDir);

    spdlog::set_pattern("[bop-shape] %v");
    const auto t0 = std::chrono::steady_clock::now();
    const bop::shape::ShapeSpec spec = bop::shape::loadShapeSpec(scene);
    for (const std::string& w : spec.warnings) spdlog::warn("{}", w);
    const bop::shape::ShapeBuild build = bop::shape::loadOrBuildShape(
        spec, noCache ? "" : cache, rebuild, [](const std::string& m) { spdlog::info("{}", m); }, threads);
    // Parts too thin for their bag, before it is built.
    for (const std::string& w : bop::shape::thinPartsWarnings(build.frames.front(), spec.bagNames()))
        spdlog::warn("{}", w);
    bop::app::printShapeReport(std::cout, spec, build);
    const auto bags = bop::app::summariseBags(build.frames.front(), spec.bagNames());
    bop::app::printBagReport(std::cout, bags);
    bop::app::writeBagsCsv(outDir + "/bags.csv", bags);
    bop::app::printTimings(std::cout, build.timings);
    if (!timingsCsv.empty()) bop::app::writeTimingsCsv(timingsCsv, build.frames.front(), build.timings);
    if (!what.empty()) {
        bop::app::exportNpy(outDir, build, what);
        spdlog::info("wrote .npy arrays (NumPy shape (nz, ny, nx[, 3])) to {}", outDir);
    }
    if (!noPng) {
        const auto files = bop::app::writeSlicePictures(outDir, build, spec.bagNames());
        spdlog::info("wrote {} slice pictures to {}", files.size(), outDir);
    }
    spdlog::info("done in {:.2f} s", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-shape", [&] { return run(argc, argv); });
}
