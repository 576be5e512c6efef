// bop-lv-phantom: writes a synthetic gated left ventricle (shape/LvPhantom.hpp) as NIfTI, one
// 4D file or a numbered series of 3D files, with its ground truth (volumes and ejection
// fraction) as CSV, for the ventricle scene (config/scenes/ventricle.toml) and for tests.
#include "bop/common/Error.hpp"
#include "bop/common/ToolMain.hpp"
#include "shape/LvPhantom.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace fs = std::filesystem;

namespace {

int run(int argc, char** argv) {
    CLI::App app{
        "bop-lv-phantom: write a synthetic gated left ventricle (a truncated prolate spheroid cavity whose "
        "volume follows a physiological curve) as NIfTI with its ground-truth volumes"};
    bop::shape::LvPhantomParams p;
    std::string out = "lv-phantom.nii.gz", truth;
    bool series = false;
    app.add_option("output", out,
                   "4D NIfTI file to write (.nii or .nii.gz); with --series, the first of the "
                   "numbered 3D files (NAME-00.nii.gz, NAME-01.nii.gz, ...)");
    app.add_flag("--series", series, "write one 3D file per frame instead of one 4D file");
    app.add_option("--frames", p.frames, "gated frames over one cycle")->check(CLI::Range(2, 64));
    app.add_option("--edv-ml", p.edvMl, "end-diastolic volume, mL")->check(CLI::PositiveNumber);
    app.add_option("--esv-ml", p.esvMl, "end-systolic volume, mL")->check(CLI::PositiveNumber);
    app.add_option("--voxel-mm", p.voxelMm, "voxel edge, mm")->check(CLI::Range(0.25, 10.0));
    app.add_option("--aspect", p.aspectEd, "long over short semi-axis at end-diastole")->check(CLI::Range(1.0, 4.0));
    app.add_option("--shortening", p.axialShortening, "fraction of the long axis lost in systole")
        ->check(CLI::Range(0.0, 0.5));
    app.add_option("--truth", truth, "ground-truth CSV (default: next to the output, NAME-truth.csv)");
    CLI11_PARSE(app, argc, argv);
    if (p.esvMl >= p.edvMl) throw bop::Error("--esv-ml", "expected an end-systolic volume below the end-diastolic one");
    std::string stem = fs::path(out).filename().string();
    const std::string ext = stem.size() > 7 && stem.ends_with(".nii.gz") ? ".nii.gz" : ".nii";
    if (!stem.ends_with(ext)) throw bop::Error(out, "expected a .nii or .nii.gz file name");
    stem.resize(stem.size() - ext.size());
    const fs::path dir = fs::path(out).parent_path();
    if (!dir.empty()) fs::create_directories(dir);
    if (truth.empty()) truth = (dir / (stem + "-truth.csv")).string();

    const bop::shape::LvPhantom lv = bop::shape::makeLvPhantom(p);
    const auto& d = lv.frames.front().dims;
    std::vector<std::string> written;
    if (series) {
        for (std::size_t f = 0; f < lv.frames.size(); ++f) {
            char name[32];
            std::snprintf(name, sizeof name, "-%02zu", f);
            written.push_back((dir / (stem + name + ext)).string());
            bop::shape::writeNifti(written.back(), lv.frames[f], "uint8");
        }
    } else {
        written.push_back(out);
        bop::shape::writeNifti4d(out, lv.frames, "uint8");
    }
    std::ofstream csv(truth);
    if (!csv) throw bop::Error(truth, "cannot write the ground truth");
    csv << "frame,phase,volume_ml,voxel_volume_ml\n";
    for (std::size_t f = 0; f < lv.frames.size(); ++f)
        csv << f << ',' << lv.phase[f] << ',' << lv.volumeMl[f] << ',' << lv.voxelVolumeMl[f] << '\n';
    if (!csv.flush()) throw bop::Error(truth, "cannot write the ground truth");
    std::printf("%d frames of %d x %d x %d voxels of %.3g mm: %s%s\n", p.frames, d.nx, d.ny, d.nz, p.voxelMm,
                written.front().c_str(), series ? " ..." : "");
    std::printf("volume per frame (mL, exact / voxels):");
    for (std::size_t f = 0; f < lv.frames.size(); ++f) std::printf(" %.1f/%.1f", lv.volumeMl[f], lv.voxelVolumeMl[f]);
    std::printf("\nejection fraction: %.2f%% exact, %.2f%% from voxels; ground truth in %s\n",
                100 * lv.ejectionFraction(), 100 * lv.voxelEjectionFraction(), truth.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-lv-phantom", [&] { return run(argc, argv); });
}
