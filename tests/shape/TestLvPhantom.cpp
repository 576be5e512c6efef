// The synthetic gated left ventricle: its volume curve and ejection fraction, the shipped data
// file against the generator, and the ventricle scene's maps measured against the ground truth.
#include "TestUtil.hpp"
#include "app/scene/SceneConfig.hpp"
#include "core/Keyframes.hpp"
#include "shape/LvPhantom.hpp"
#include "shape/ShapeBuilder.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace bop;
using namespace bop::shape;

TEST_CASE("the phantom's volume curve: end-diastole 120 mL, end-systole 50 mL at frame 3, exact shapes", "[lv]") {
    const LvPhantomParams p;
    CHECK(lvVolumeMl(p, 0.0) == Approx(120));
    CHECK(lvVolumeMl(p, 3.0 / 8) == Approx(50));
    for (double phase = 0; phase < 1; phase += 0.01) {
        CHECK(lvVolumeMl(p, phase) <= 120 + 1e-9);
        CHECK(lvVolumeMl(p, phase) >= 50 - 1e-9);
        const LvShape s = lvShapeFor(p, lvVolumeMl(p, phase));
        CHECK(s.volumeMl == Approx(lvVolumeMl(p, phase)));
        CHECK(s.a > s.b);  // prolate
    }
    CHECK(lvVolumeMl(p, 0.99) == Approx(lvVolumeMl(p, -0.01)));  // periodic
    // Ejection is monotone, filling too (up to the atrial kick).
    for (double phase = 0.05; phase < 0.37; phase += 0.01) CHECK(lvVolumeMl(p, phase + 0.01) <= lvVolumeMl(p, phase));
    for (double phase = 0.45; phase < 0.99; phase += 0.01) CHECK(lvVolumeMl(p, phase + 0.01) >= lvVolumeMl(p, phase));
    // The typical pressure curve peaks at 120 mmHg in ejection and is low in filling.
    double peak = 0, at = 0;
    for (double phase = 0; phase < 1; phase += 0.001)
        if (lvTypicalPressureMmHg(phase) > peak) peak = lvTypicalPressureMmHg(phase), at = phase;
    CHECK(peak == Approx(120).margin(0.01));
    CHECK(at > 0.05);
    CHECK(at < 3.0 / 8);
    CHECK(lvTypicalPressureMmHg(0.6) < 10);
}

TEST_CASE("the phantom's voxels give its ejection fraction within 1 percentage point", "[lv]") {
    for (double voxelMm : {1.5, 2.0, 2.5}) {
        LvPhantomParams p;
        p.voxelMm = voxelMm;
        const LvPhantom lv = makeLvPhantom(p);
        INFO("voxel " << voxelMm << " mm: EF " << lv.ejectionFraction() << " exact, " << lv.voxelEjectionFraction()
                      << " voxels");
        CHECK(lv.ejectionFraction() == Approx(70.0 / 120));
        CHECK(std::abs(lv.voxelEjectionFraction() - lv.ejectionFraction()) < 0.01);
        for (std::size_t f = 0; f < lv.frames.size(); ++f)
            CHECK(lv.voxelVolumeMl[f] == Approx(lv.volumeMl[f]).epsilon(0.03));
    }
}

TEST_CASE("the shipped lv-phantom.nii.gz is the generator's default output", "[lv]") {
    const std::vector<ScalarImage> shipped = loadNifti(test::sourceDir() + "/config/data/lv-phantom.nii.gz");
    const LvPhantom lv = makeLvPhantom(LvPhantomParams{});
    REQUIRE(shipped.size() == lv.frames.size());
    for (std::size_t f = 0; f < shipped.size(); ++f) {
        CHECK(shipped[f].dims.nx == lv.frames[f].dims.nx);
        CHECK(shipped[f].dims.nz == lv.frames[f].dims.nz);
        CHECK(shipped[f].spacingMm.x() == Approx(2.0));
        CHECK(shipped[f].values == lv.frames[f].values);
    }
}

TEST_CASE("the ventricle scene's 8 maps hold the cavity volumes: ejection fraction within 1 point of the truth",
          "[lv]") {
    const app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/ventricle.toml");
    CHECK(scene.model->keyframes.frames == 8);
    CHECK(scene.model->keyframes.frameDuration == Approx(4.0));
    REQUIRE(scene.pressure);
    const ShapeBuild b = buildShape(*scene.shape);
    REQUIRE(b.frames.size() == 8);
    const LvPhantom truth = makeLvPhantom(LvPhantomParams{});
    std::vector<double> ml;
    for (std::size_t f = 0; f < 8; ++f) {
        const Eigen::Vector3d all = Eigen::Vector3d::Constant(1e300);
        const core::MapVolume v = core::countMapVolume(b.frames[f], -all, all);
        ml.push_back(v.bagVoxels * std::pow(b.frames[f].grid.voxelMm, 3) / 1000);
        CHECK(ml.back() == Approx(truth.volumeMl[f]).epsilon(0.03));
        CHECK(v.volumeVoxels < v.bagVoxels);
    }
    INFO("EF from the maps " << ejectionFraction(ml) << ", truth " << truth.ejectionFraction());
    CHECK(std::abs(ejectionFraction(ml) - truth.ejectionFraction()) < 0.01);
    CHECK(std::min_element(ml.begin(), ml.end()) - ml.begin() == 3);  // end-systole at frame 3
}

TEST_CASE("a numbered series of 3D files loads as the same 8 keyframes as the 4D file", "[lv]") {
    test::TempDir dir("lv-series");
    const LvPhantom lv = makeLvPhantom(LvPhantomParams{});
    std::string files;
    for (std::size_t f = 0; f < lv.frames.size(); ++f) {
        const std::string name = "lv-" + std::to_string(f) + ".nii.gz";
        writeNifti(dir.file(name), lv.frames[f], "uint8");
        files += (f ? ", '" : "'") + name + "'";
    }
    const std::string scene =
        test::writeText(dir.file("series.toml"),
                        "[grid]\nr0_voxels = 2.0\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfiles = [" + files +
                            "]\nlabel = 1\nboundary_smoothing_voxels = 0\n"  // every voxel as the files hold it
                            "[keyframes]\nperiod = 32.0\n");
    const app::Scene s = app::loadScene(scene);
    CHECK(s.model->keyframes.frames == 8);
    CHECK(s.model->keyframes.frameDuration == Approx(4.0));
    const ShapeBuild b = buildShape(*s.shape);
    REQUIRE(b.frames.size() == 8);
    std::vector<double> ml;
    for (const GradientMap& m : b.frames) {
        const Eigen::Vector3d all = Eigen::Vector3d::Constant(1e300);
        ml.push_back(core::countMapVolume(m, -all, all).bagVoxels * std::pow(m.grid.voxelMm, 3) / 1000);
    }
    for (std::size_t f = 0; f < 8; ++f) CHECK(ml[f] == Approx(lv.voxelVolumeMl[f]).epsilon(1e-9));  // every voxel kept
    CHECK(std::abs(ejectionFraction(ml) - lv.ejectionFraction()) < 0.01);
}
