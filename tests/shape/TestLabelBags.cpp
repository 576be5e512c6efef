// One bag per label of a segmentation (shape/ImageBags.hpp, `labels`): three touching organs, one
// more nested in one of them through a label list, a speck too small for a bag; names and colours
// from an ITK-SNAP or 3D Slicer label table; bad label lists and tables stop with the key or line.
#include "ShapeTestUtil.hpp"
#include "app/scene/SceneConfig.hpp"
#include "shape/ScalarImage.hpp"
#include "shape/ShapeSpec.hpp"

#include <catch2/catch.hpp>

using namespace bop;
using namespace bop::shape;

namespace {

// 40 x 24 x 24 voxels of 1 mm: boxes of labels 6 | 10 | 15 side by side and touching along x,
// a ball of label 20 inside box 6, a 3-voxel speck of label 30 apart and a 4-voxel piece of label
// 15 beside its box.
ScalarImage organs() {
    const Dims d{40, 24, 24};
    ScalarImage img{d, Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero(), std::vector<float>(d.count(), 0.f)};
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                float v = 0;
                if (j >= 3 && j < 21 && k >= 3 && k < 21) v = i >= 2 && i < 14 ? 6.f : i >= 14 && i < 26 ? 10.f : 0.f;
                if (j >= 3 && j < 21 && k >= 3 && k < 21 && i >= 26 && i < 38) v = 15.f;
                if ((Eigen::Vector3d(i, j, k) + Eigen::Vector3d::Constant(0.5) - Eigen::Vector3d(8, 12, 12)).norm() <
                    3.6)
                    v = 20.f;
                img.values[d.index(i, j, k)] = v;
            }
    for (int i = 0; i < 3; ++i) img.values[d.index(1 + i, 1, 1)] = 30.f;
    for (int i = 0; i < 4; ++i) img.values[d.index(30 + i, 22, 22)] = 15.f;  // a speck of the heart's label, apart
    return img;
}

const char* kItkSnap =
    "# ITK-SNAP Label Description File\n"
    "    0     0    0    0        0  0  0    \"Clear Label\"\n"
    "    6   200   80   60        1  1  1    \"liver\"\n"
    "   10   230  200  100        1  1  1    \"stomach wall\"\n"
    "   15   180   30   40        1  1  1    \"heart\"\n";

}  // namespace

TEST_CASE("each label of a multi-label image becomes its bag", "[shape][segmentation][bags]") {
    test::TempDir dir("label-bags");
    writeNifti(dir.file("organs.nii.gz"), organs(), "uint8");
    test::writeText(dir.file("labels.txt"), kItkSnap);
    const std::string head =
        "[grid]\nr0_voxels = 2.0\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfile = 'organs.nii.gz'\n";

    SECTION("labels = 'all' with a label table: one bag per label, named and coloured, the specks skipped") {
        const std::string scene =
            test::writeText(dir.file("all.toml"), head + "labels = 'all'\nlabel_table = 'labels.txt'\n");
        const app::Scene s = app::loadScene(scene);
        REQUIRE(s.shape);
        CHECK(s.shape->bagNames() == std::vector<std::string>{"liver", "stomach_wall", "heart", "label-20"});
        REQUIRE(s.shape->warnings.size() == 2);
        CHECK_THAT(s.shape->warnings[0], Catch::Contains("shape.bag[0]") && Catch::Contains("label 15 ('heart')") &&
                                             Catch::Contains("1 piece(s) of 4 image voxels") &&
                                             Catch::Contains("fewer than the 34") && Catch::EndsWith("skipped"));
        CHECK_THAT(s.shape->warnings[1], Catch::Contains("shape.bag[0]") && Catch::Contains("label 30") &&
                                             Catch::Contains("3 voxels") && Catch::Contains("skipped"));
        REQUIRE(s.model->speciesCount() == 8);
        CHECK(s.model->species[1].name == "liver-surface");
        CHECK(s.model->species[6].name == "heart-volume");
        CHECK(s.model->species[1].colour[0] == Approx(200 / 255.0));
        CHECK(s.model->species[2].colour[0] == Approx(0.6 * 200 / 255.0));
        // The map: each organ's centre in its own volume species; the touching faces each a
        // surface of its own; the ball, a hole in the liver label, a bag beside the liver's.
        const GradientMap m = buildShape(*s.shape).frames[0];
        const Eigen::Vector3d lo = m.grid.originMm;
        const auto occAt = [&](double x, double y, double z) {
            const Eigen::Vector3i c = ((Eigen::Vector3d(x, y, z) - lo) / m.grid.voxelMm).array().floor().cast<int>();
            return int(m.occ[m.dims().index(c.x(), c.y(), c.z())]);
        };
        CHECK(occAt(20.5, 12.5, 12.5) == 4);  // stomach
        CHECK(occAt(32.5, 12.5, 12.5) == 6);  // heart
        CHECK(occAt(8.5, 12.5, 12.5) == 8);   // the ball of label 20
        CHECK(occAt(8.5, 5.5, 12.5) == 2);    // liver, beside the ball
        CHECK(occAt(13.5, 12.5, 12.5) == 1);  // liver | stomach: the liver's last layer
        CHECK(occAt(14.5, 12.5, 12.5) == 3);  // and the stomach's first
        CHECK(occAt(25.5, 12.5, 12.5) == 3);
        CHECK(occAt(26.5, 12.5, 12.5) == 5);
        for (int i = 0; i < 4; ++i) CHECK(occAt(30.5 + i, 22.5, 22.5) == 0);  // the heart's speck, left out
        CHECK(m.bagParent == std::vector<std::uint8_t>{0, 0, 0, 0, 0});
    }
    SECTION("a label list nests the ball in a bag of the liver with it") {
        const std::string scene =
            test::writeText(dir.file("nested.toml"),
                            "[grid]\nr0_voxels = 2.0\n[shape]\n[[shape.bag]]\nname = 'liver'\nsource = "
                            "'nifti'\nfile = 'organs.nii.gz'\nlabel = [6, 20]\n[[shape.bag]]\nsource = "
                            "'nifti'\nfile = 'organs.nii.gz'\nlabels = [20, 10]\n");
        const ShapeSpec spec = loadShapeSpec(scene);
        CHECK(spec.bagNames() == std::vector<std::string>{"liver", "label-20", "label-10"});
        const GradientMap m = buildShape(spec).frames[0];
        CHECK(m.bagParent == std::vector<std::uint8_t>{0, 0, 1, 0});  // the ball inside the liver
    }
    SECTION("a 3D Slicer colour table names them too") {
        test::writeText(dir.file("slicer.ctbl"), "# Color table\n0 Background 0 0 0 0\n10 Stomach 230 200 100 255\n");
        const ShapeSpec spec = loadShapeSpec(
            test::writeText(dir.file("slicer.toml"), head + "labels = [10]\nlabel_table = 'slicer.ctbl'\n"));
        CHECK(spec.bagNames() == std::vector<std::string>{"Stomach"});
    }
    SECTION("bad label lists and tables stop with the key, the file and the line") {
        CHECK_THROWS_WITH(loadShapeSpec(test::writeText(dir.file("absent.toml"), head + "labels = [6, 99]\n")),
                          Catch::Contains("shape.bag[0].labels") && Catch::Contains("label 99 is not in file") &&
                              Catch::Contains("holds only 6)"));
        CHECK_THROWS_WITH(loadShapeSpec(test::writeText(dir.file("both.toml"), head + "labels = [6]\nlabel = 6\n")),
                          Catch::Contains("shape.bag[0].labels") && Catch::Contains("not with 'label'"));
        CHECK_THROWS_WITH(loadShapeSpec(test::writeText(dir.file("word.toml"), head + "labels = 'some'\n")),
                          Catch::Contains("shape.bag[0].labels") && Catch::Contains("\"all\""));
        test::writeText(dir.file("bad.txt"), "# labels\n6 200 80 60 1 1 1 \"liver\"\n10 lots of words\n");
        CHECK_THROWS_WITH(
            loadShapeSpec(test::writeText(dir.file("badtable.toml"), head + "labels = [6]\nlabel_table = 'bad.txt'\n")),
            Catch::Contains("bad.txt") && Catch::Contains("line 3") && Catch::Contains("ITK-SNAP"));
    }
}
