// Segmentations at the organ's size: the grid cut to the bag's box (its map equal to the
// whole-scan map's window), label lists, and components = "largest" with the sizes it dropped.
#include "ShapeTestUtil.hpp"
#include "shape/ImageRasterizer.hpp"
#include "shape/ScalarImage.hpp"

#include <catch2/catch.hpp>

using namespace bop;
using namespace bop::shape;

namespace {

// A 90 x 80 x 60 scan of 1.5 mm voxels: label 5 a ball (radius 9 voxels) off-centre, label 7 a
// smaller ball elsewhere, label 5 also a 3-voxel speck far from its ball, the rest 0.
ScalarImage scan() {
    ScalarImage img{{90, 80, 60}, Eigen::Vector3d::Constant(1.5), Eigen::Vector3d::Zero(), {}};
    img.values.assign(img.dims.count(), 0.f);
    for (std::size_t v = 0; v < img.dims.count(); ++v) {
        const Eigen::Vector3d c = img.dims.coords(v).cast<double>() + Eigen::Vector3d::Constant(0.5);
        if ((c - Eigen::Vector3d(60, 25, 30)).norm() < 9) img.values[v] = 5.f;
        if ((c - Eigen::Vector3d(20, 55, 25)).norm() < 6) img.values[v] = 7.f;
    }
    for (int i = 0; i < 3; ++i) img.values[img.dims.index(10 + i, 10, 50)] = 5.f;
    return img;
}

std::size_t objectVoxels(const GradientMap& m) {
    std::size_t n = 0;
    for (auto o : m.occ) n += o != 0;
    return n;
}

std::size_t valued(const ScalarImage& img, float value) {
    return std::size_t(std::count(img.values.begin(), img.values.end(), value));
}

}  // namespace

TEST_CASE("a label's map is cut to its box and equals the whole scan's map there", "[shape][segmentation]") {
    test::TempDir dir("crop");
    const ScalarImage img = scan();
    writeNifti(dir.file("scan.nii.gz"), img, "int16");
    const std::string scene = test::writeText(
        dir.file("organ.toml"),
        "[grid]\npadding_voxels = 4\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfile = 'scan.nii.gz'\nlabel = 7\n");
    const ShapeSpec spec = loadShapeSpec(scene);
    const GradientMap cut = buildShape(spec).frames[0];
    CHECK(cut.grid.voxelMm == 1.5);
    CHECK(cut.dims() == (Dims{12 + 8, 12 + 8, 12 + 8}));  // the ball's 12 voxels plus 4 each side
    CHECK(objectVoxels(cut) == valued(img, 7.f));

    // The whole scan on its own lattice, 4 voxels of padding: the map this bag had before the cut.
    VoxelGrid whole{{98, 88, 68}, Eigen::Vector3d::Constant(-6.0), 1.5};
    Mask mask;
    rasterizeImage(img, ImageSelect{ImageSelect::Mode::Label, 0.5, {7}}, whole, mask);
    Volume<std::uint8_t> depth(whole.dims, 0);
    depth.data.assign(mask.data.begin(), mask.data.end());
    const GradientMap full = buildGradientMap(whole, depth, spec.grid.r0Voxels, spec.geometry);
    const Eigen::Vector3d shift = (cut.grid.originMm - whole.originMm) / 1.5;  // whole voxels
    REQUIRE(shift.isApprox(shift.array().round().matrix()));
    const Eigen::Vector3i at = shift.array().round().cast<int>();
    std::size_t differ = 0, normals = 0;
    for (std::size_t v = 0; v < cut.occ.size(); ++v) {
        const Eigen::Vector3i c = cut.dims().coords(v) + at;
        const std::size_t w = full.dims().index(c.x(), c.y(), c.z());
        differ += cut.occ[v] != full.occ[w] || cut.delta(v).squaredNorm() != full.delta(w).squaredNorm();
        normals += (cut.nearestSurface(v).normal - full.nearestSurface(w).normal).norm() > 1e-5f;
    }
    CHECK(differ == 0);
    CHECK(normals == 0);
    CHECK(cut.occ.size() * 50 < full.occ.size());  // the map follows the organ, not the scan
}

TEST_CASE("label lists and components = \"largest\"", "[shape][segmentation]") {
    test::TempDir dir("labels");
    const ScalarImage img = scan();
    writeNifti(dir.file("scan.nii"), img, "uint8");
    // The selection itself, voxel for voxel: without the boundary smoothing that images get by default.
    const std::string head =
        "[grid]\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfile = 'scan.nii'\nboundary_smoothing_voxels = 0\n";
    SECTION("a list selects every label in it") {
        const ShapeSpec spec = loadShapeSpec(test::writeText(dir.file("list.toml"), head + "label = [5, 7]\n"));
        CHECK(spec.warnings.empty());
        CHECK(objectVoxels(buildShape(spec).frames[0]) == valued(img, 5.f) + valued(img, 7.f));
    }
    SECTION("every piece is kept by default") {
        const ShapeSpec spec = loadShapeSpec(test::writeText(dir.file("all.toml"), head + "label = 5\n"));
        CHECK(objectVoxels(buildShape(spec).frames[0]) == valued(img, 5.f));
    }
    SECTION("largest keeps the ball and names the speck it dropped") {
        const ShapeSpec spec =
            loadShapeSpec(test::writeText(dir.file("largest.toml"), head + "label = 5\ncomponents = 'largest'\n"));
        REQUIRE(spec.warnings.size() == 1);
        const std::size_t ball = valued(img, 5.f) - 3;
        CHECK_THAT(spec.warnings[0], Catch::Contains("shape.bag[0]") &&
                                         Catch::Contains("1 piece(s) of 3 image voxels") &&
                                         Catch::Contains("kept " + std::to_string(ball)));
        CHECK(objectVoxels(buildShape(spec).frames[0]) == ball);
    }
    SECTION("a label absent from the image, or a bad components value, stops with the key") {
        const std::string absent = test::writeText(dir.file("absent.toml"), head + "label = [5, 9]\n");
        // 5 is there: a list needs one label present, and selects what is present.
        CHECK(objectVoxels(buildShape(loadShapeSpec(absent)).frames[0]) == valued(img, 5.f));
        const std::string none = test::writeText(dir.file("none.toml"), head + "label = [8, 9]\n");
        CHECK_THROWS_WITH(loadShapeSpec(none),
                          Catch::Contains("shape.bag[0].label") && Catch::Contains("selects no voxels"));
        const std::string bad = test::writeText(dir.file("bad.toml"), head + "label = 5\ncomponents = 'biggest'\n");
        CHECK_THROWS_WITH(loadShapeSpec(bad), Catch::Contains("shape.bag[0].components") && Catch::Contains("largest"));
    }
}
