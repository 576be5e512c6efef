// bop-material SCENE.toml: virtual material tests on the scene's first bag, placed and settled as
// bop-server settles it: the sphere pressed into it (indentation, against Hertz) or the bag
// compressed between plates (apparent Young's modulus and Poisson ratio). Writes a CSV in mm, N
// and kPa; scripts/bench/material.sh runs it over materials and resolutions (docs/physics.md §8.4).
#include "app/material/VirtualTests.hpp"
#include "app/runs/Settling.hpp"
#include "app/scene/RunStart.hpp"
#include "app/scene/SceneConfig.hpp"
#include "bop/common/ToolMain.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace fs = std::filesystem;
using namespace bop;

namespace {

void say(const std::string& line) {
    std::cout << "[bop-material] " << line << std::endl;
}

int run(int argc, char** argv) {
    CLI::App app{
        "bop-material: virtual material tests (indentation by the scene's probe sphere, compression "
        "between plates) on a scene's placed and settled bag; CSV in mm, N and kPa"};
    std::string scenePath, test = "indent", out = "material.csv";
    std::vector<double> depthsMm{0.2, 0.4, 0.6, 0.8, 1.0}, strains{0.01, 0.02, 0.03, 0.04, 0.05};
    double baseMm = 0, plateMm = 0;
    std::vector<double> xyMm;
    long long maxSteps = 20000;
    app.add_option("scene", scenePath, "scene file (TOML) with [[material]] tables")->required();
    app.add_option("--test", test, "indent or compress")->check(CLI::IsMember({"indent", "compress"}));
    app.add_option("--out", out, "CSV file to write");
    app.add_option("--depths-mm", depthsMm, "indent: the sphere's depths beyond first contact, mm, comma separated")
        ->delimiter(',')
        ->check(CLI::PositiveNumber);
    app.add_option("--at-mm", xyMm, "indent: x y of the sphere's axis from the bag's centre, mm (default 0 0)")
        ->expected(2);
    app.add_option("--base-mm", baseMm, "indent: depth of the held base, mm (default r0)");
    app.add_option("--strains", strains, "compress: the plates' approach over the height, comma separated")
        ->delimiter(',')
        ->check(CLI::Range(0.0, 0.5));
    app.add_option("--plate-mm", plateMm, "compress: depth of each plate's held layer, mm (default r0)");
    app.add_option("--max-steps", maxSteps, "the most minimiser steps per load step");
    CLI11_PARSE(app, argc, argv);

    const app::Scene scene = app::loadScene(scenePath);
    if (scene.materials.empty()) throw Error(scenePath, "material: the scene has no [[material]] table");
    const UnitSystem& u = scene.model->units;
    for (const std::string& line :
         app::calibrationReport(*scene.calibration, scene.materials, scene.model->integration.dt))
        say(line);
    const fs::path dir = fs::path(out).parent_path().empty() ? fs::path(".") : fs::path(out).parent_path();
    fs::create_directories(dir);
    app::RunStart s =
        app::startRun(scene, (dir / (fs::path(out).stem().string() + ".bopgm")).string(), "", true, [] {});
    app::useSettleTimeStep(scene, s);
    core::Run runner(s.model, s.particles, std::move(s.options));
    const auto t0 = std::chrono::steady_clock::now();
    app::Settling settling(runner, scene.run);
    while (!settling.afterStep(runner) && runner.stepNumber() < scene.run.steps) runner.step();
    const double settleS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    say("settled at step " + std::to_string(runner.stepNumber()) + " in " + std::to_string(settleS) + " s, " +
        std::to_string(runner.simulation().particles().size()) + " particles");

    app::Relaxation relax;
    relax.maxSteps = maxSteps;
    const double r0 = bop::kR0;
    const app::Material& m = scene.materials.front();
    std::ofstream csv(out);
    if (!csv) throw Error(out, "cannot write");
    if (test == "indent") {
        const auto& p = runner.simulation().particles();
        Eigen::Vector2d xy = Eigen::Vector2d::Zero();
        for (const auto& x : p.pos) xy += x.head<2>();
        xy /= double(p.size());
        if (xyMm.size() == 2) xy += Eigen::Vector2d(u.fromMm(xyMm[0]), u.fromMm(xyMm[1]));
        std::vector<double> depths;
        for (double d : depthsMm) depths.push_back(u.fromMm(d));
        const double R = s.model->probeSphere ? s.model->probeSphere->radius : 0;
        const auto points = app::indent(runner, xy, depths, baseMm > 0 ? u.fromMm(baseMm) : r0, relax, say);
        const double eStar = m.youngKpa * 1e3 / (1 - m.poisson * m.poisson);  // Pa
        csv << "depth_mm,force_n,hertz_n,ratio,steps\n";
        // Hertz's E fitted by least squares over the depths up to 0.2 R: F = E g(d).
        double fg = 0, gg = 0;
        for (const auto& pt : points) {
            if (pt.depth > 0.2 * R * (1 + 1e-9)) continue;
            const double g = 4.0 / 3.0 / (1 - m.poisson * m.poisson) * std::sqrt(R) * std::pow(pt.depth, 1.5);
            fg += pt.force * g;
            gg += g * g;
        }
        if (gg > 0)
            say("Hertz fit over depths up to 0.2 R: E " + std::to_string(u.toKpa(fg / gg)) + " kPa, stated " +
                std::to_string(m.youngKpa) + " kPa");
        for (const auto& pt : points) {
            const double dM = u.toMm(pt.depth) * 1e-3, rM = u.toMm(R) * 1e-3;
            const double hertz = 4.0 / 3.0 * eStar * std::sqrt(rM) * std::pow(dM, 1.5);
            char line[200];
            std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.5f,%lld\n", u.toMm(pt.depth), u.toN(pt.force), hertz,
                          u.toN(pt.force) / hertz, pt.steps);
            csv << line;
        }
    } else {
        const auto points = app::compress(runner, strains, plateMm > 0 ? u.fromMm(plateMm) : r0, relax, say);
        csv << "strain,stress_kpa,lateral_strain,apparent_e_kpa,poisson,steps\n";
        for (const auto& pt : points) {
            char line[200];
            std::snprintf(line, sizeof line, "%.6g,%.6g,%.6g,%.6g,%.5f,%lld\n", pt.strain, u.toKpa(pt.stress),
                          pt.lateralStrain, u.toKpa(pt.stress) / pt.strain, pt.lateralStrain / pt.strain, pt.steps);
            csv << line;
        }
    }
    say("wrote " + out);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-material", [&] { return run(argc, argv); });
}
