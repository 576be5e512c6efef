// Whole scenes through the builder: mesh vs analytic torus, superellipsoid volumes, image
// sequences on one grid, and invariants of every shipped scene's map.
#include "ShapeTestUtil.hpp"
#include "shape/ScalarImage.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

using namespace bop;
using namespace bop::shape;

namespace {

std::size_t objectVoxels(const GradientMap& m) {
    std::size_t n = 0;
    for (auto o : m.occ) n += o != 0;
    return n;
}

const std::string kGrid = "[grid]\nvoxel_size_mm = 1.0\nr0_voxels = 2.0\nsize_voxels = [90, 90, 34]\n[shape]\n";

}  // namespace

TEST_CASE("the voxelised torus mesh agrees with the analytic torus", "[shape][scene][torus]") {
    test::TempDir dir("torus");
    const std::string model = test::sourceDir() + "/config/models/torus.obj";
    const std::string meshScene =
        test::writeText(dir.file("mesh.toml"), kGrid + "[[shape.bag]]\nsource = 'mesh'\nfile = '" + model + "'\n");
    const std::string torusScene =
        test::writeText(dir.file("analytic.toml"),
                        kGrid + "[[shape.bag]]\nsource = 'torus'\nmajor_radius_mm = 30.0\nminor_radius_mm = 12.0\n");
    const ShapeBuild mesh = buildShape(loadShapeSpec(meshScene));
    const ShapeBuild torus = buildShape(loadShapeSpec(torusScene));
    const GradientMap &a = mesh.frames[0], &b = torus.frames[0];
    REQUIRE(a.dims() == b.dims());
    CHECK(a.grid.originMm.isApprox(b.grid.originMm));
    std::size_t differ = 0;
    for (std::size_t v = 0; v < a.occ.size(); ++v) differ += (a.occ[v] != 0) != (b.occ[v] != 0);
    const double exact = 2 * M_PI * M_PI * 30.0 * 12.0 * 12.0;  // mm^3, 1 mm voxels
    INFO("mesh " << objectVoxels(a) << " voxels, analytic " << objectVoxels(b) << ", 2 pi^2 R r^2 = " << exact
                 << ", differing voxels " << differ);
    CHECK(double(differ) < 0.01 * double(objectVoxels(b)));
    CHECK(double(objectVoxels(a)) == Approx(exact).epsilon(0.02));
    CHECK(double(objectVoxels(b)) == Approx(exact).epsilon(0.02));
}

TEST_CASE("an open mesh in file units: fit_voxels scales it, the scene warns what was mended", "[shape][scene]") {
    // The torus in metres (1/1000 of its mm coordinates) with a hole: fit_voxels = 42 spans its
    // 84 mm across 42 voxels of 2 mm, i.e. the same solid as scale_mm = 1000.
    test::TempDir dir("fit");
    std::ifstream in(test::sourceDir() + "/config/models/torus.obj");
    std::ofstream out(dir.file("metres.obj"));
    std::string line;
    int faces = 0;
    while (std::getline(in, line)) {
        if (line.rfind("v ", 0) == 0) {
            std::istringstream f(line.substr(2));
            double x, y, z;
            f >> x >> y >> z;
            out << "v " << x / 1000 << ' ' << y / 1000 << ' ' << z / 1000 << '\n';
        } else if (line.rfind("f ", 0) != 0 || ++faces != 500) {
            out << line << '\n';  // face 500 left out: a hole
        }
    }
    out.close();
    const std::string grid =
        "[grid]\nvoxel_size_mm = 2.0\n[shape]\n[[shape.bag]]\nsource = 'mesh'\nfile = 'metres.obj'\n";
    const ShapeSpec fitted = loadShapeSpec(test::writeText(dir.file("fit.toml"), grid + "fit_voxels = 42\n"));
    REQUIRE(fitted.warnings.size() == 1);
    CHECK_THAT(fitted.warnings[0], Catch::Contains("shape.bag[0]") && Catch::Contains("metres.obj") &&
                                       Catch::Contains("3 boundary edges") && Catch::Contains("winding number"));
    const Eigen::Vector3d sides = fitted.bags[0].source->boundsMm(0).sizes();
    CHECK(sides.maxCoeff() == Approx(84.0).epsilon(1e-6));
    const ShapeSpec scaled = loadShapeSpec(test::writeText(dir.file("scaled.toml"), grid + "scale_mm = 1000.0\n"));
    const GradientMap a = buildShape(fitted).frames[0], b = buildShape(scaled).frames[0];
    const double exact = 2 * M_PI * M_PI * 30.0 * 12.0 * 12.0 / 8.0;  // voxels of 8 mm^3
    INFO("fitted " << objectVoxels(a) << ", scaled " << objectVoxels(b) << ", analytic " << exact);
    CHECK(double(objectVoxels(a)) == Approx(exact).epsilon(0.03));
    // Float rounding of 84 mm decides whether the grid is 42 or 43 voxels wide (half a voxel of shift).
    CHECK(double(objectVoxels(a)) == Approx(double(objectVoxels(b))).epsilon(0.01));
}

TEST_CASE("superellipsoid voxel volumes match the analytic volume", "[shape][scene]") {
    test::TempDir dir("superellipsoid");
    for (const auto& [e1, e2] : {std::pair{1.0, 1.0}, {2.6, 2.6}, {0.5, 1.5}}) {
        SuperellipsoidParams p;
        p.radiiMm = {20, 16, 12};
        p.e1 = e1;
        p.e2 = e2;
        const std::string scene = test::writeText(
            dir.file("s.toml"),
            "[grid]\nvoxel_size_mm = 0.5\n[shape]\n[[shape.bag]]\nsource = 'superellipsoid'\nradii_mm = [20, 16, 12]\n"
            "exponents = [" +
                std::to_string(e1) + ", " + std::to_string(e2) + "]\n");
        const ShapeBuild s = buildShape(loadShapeSpec(scene));
        const double volume = double(objectVoxels(s.frames[0])) * 0.125;
        INFO("exponents " << e1 << ", " << e2);
        CHECK(volume == Approx(superellipsoidVolume(p)).epsilon(0.02));
    }
}

TEST_CASE("image sequences give one map per frame on one grid", "[shape][scene][sequence]") {
    test::TempDir dir("sequence");
    std::vector<ScalarImage> frames;
    for (int f = 0; f < 3; ++f) {
        ScalarImage img;
        img.dims = {32, 30, 28};
        img.spacingMm = Eigen::Vector3d::Constant(1.5);
        img.originMm.setZero();
        img.values.assign(img.dims.count(), 0.f);
        for (std::size_t v = 0; v < img.dims.count(); ++v) {
            const Eigen::Vector3d c = img.dims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
            if ((c - Eigen::Vector3d(16, 15, 14)).norm() < 6 + 2 * f) img.values[v] = 3.f;
        }
        writeNifti(dir.file("lv_" + std::to_string(f) + ".nii.gz"), img);
        frames.push_back(img);
    }
    writeNifti4d(dir.file("lv4d.nii"), frames);
    const std::string body =
        "[grid]\nr0_voxels = 2.0\npadding_voxels = 2\n[shape]\n[[shape.bag]]\nname = 'lv'\nlabel = 3\n";
    const ShapeBuild series = buildShape(loadShapeSpec(test::writeText(
        dir.file("series.toml"), body + "source = 'nifti'\nfiles = ['lv_0.nii.gz', 'lv_1.nii.gz', 'lv_2.nii.gz']\n")));
    const ShapeBuild four = buildShape(
        loadShapeSpec(test::writeText(dir.file("four.toml"), body + "source = 'nifti'\nfile = 'lv4d.nii'\n")));
    REQUIRE(series.frames.size() == 3);
    REQUIRE(four.frames.size() == 3);
    // The grid is the box of the label in every frame (the largest sphere, radius 10 voxels: 20
    // voxels across) plus 2 voxels each side, not the 32 x 30 x 28 image.
    Eigen::Vector3i lo = Eigen::Vector3i::Constant(1000), hi = -lo;
    for (const auto& img : frames)
        for (std::size_t v = 0; v < img.dims.count(); ++v)
            if (img.values[v] == 3.f) lo = lo.cwiseMin(img.dims.coords(v)), hi = hi.cwiseMax(img.dims.coords(v));
    REQUIRE(hi - lo == Eigen::Vector3i::Constant(19));
    for (int f = 0; f < 3; ++f) {
        CHECK(series.frames[f].dims() == (Dims{24, 24, 24}));
        CHECK(series.frames[f].grid.voxelMm == 1.5);  // from the image spacing
        CHECK(series.frames[f].occ == four.frames[f].occ);
        std::size_t inImage = 0;
        for (float x : frames[f].values) inImage += x == 3.f;
        CHECK(objectVoxels(series.frames[f]) == inImage);
    }
    CHECK(objectVoxels(series.frames[0]) < objectVoxels(series.frames[1]));
    CHECK(objectVoxels(series.frames[1]) < objectVoxels(series.frames[2]));
}

TEST_CASE("every shipped scene builds a map whose vectors are exact nearest-surface vectors", "[shape][scene]") {
    const auto dir = std::filesystem::path(test::sourceDir()) / "config" / "scenes";
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".toml") continue;
        const std::string text = [&] {
            std::ifstream f(entry.path());
            return std::string(std::istreambuf_iterator<char>(f), {});
        }();
        if (text.find("[shape]") == std::string::npos) continue;  // bulk material, no map
        ++scenes;
        const ShapeSpec spec = loadShapeSpec(entry.path().string());
        const ShapeBuild b = buildShape(spec);
        const GradientMap& m = b.frames[0];
        INFO(entry.path());
        std::size_t wrong = 0;
        for (const auto& sv : m.surface) wrong += m.delta(sv.voxel) != Eigen::Vector3i::Zero();
        std::mt19937 rng(1);
        std::uniform_int_distribution<std::size_t> pick(0, m.occ.size() - 1);
        for (int t = 0; t < 100; ++t) {
            const std::size_t v = pick(rng);
            int best = INT32_MAX;
            for (const auto& sv : m.surface)
                best = std::min(best, (m.dims().coords(sv.voxel) - m.dims().coords(v)).squaredNorm());
            wrong += m.delta(v).squaredNorm() != best;
        }
        CHECK(wrong == 0);
        CHECK(int(spec.bags.size()) == m.bagCount);
    }
    CHECK(scenes >= 5);
}
