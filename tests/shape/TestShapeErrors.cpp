// Every malformed shape input gives a bop::Error that names the file and the key and says
// what was expected (issue 2: missing file, flat mesh, empty bitmap, unknown key, wrong unit or
// type).
#include "ShapeTestUtil.hpp"
#include "shape/ScalarImage.hpp"

#include <catch2/catch.hpp>

#include <fstream>

using namespace bop;
using namespace bop::shape;

namespace {

std::string errorOf(const std::string& scene) {
    try {
        buildShape(loadShapeSpec(scene));
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

const std::string kGrid = "[grid]\nvoxel_size_mm = 1.0\n[shape]\n";
const std::string kSphere = "[[shape.bag]]\nsource = 'sphere'\nradius_mm = 5.0\n";

}  // namespace

TEST_CASE("shape input errors name the file and key", "[shape][errors]") {
    test::TempDir dir("errors");
    auto scene = [&](const std::string& name, const std::string& text) {
        return test::writeText(dir.file(name), text);
    };
    using Catch::Contains;

    SECTION("missing scene file") {
        CHECK_THAT(errorOf(dir.file("nope.toml")), Contains(dir.file("nope.toml")) && Contains("file not found"));
    }
    SECTION("TOML syntax error") {
        const auto s = scene("syntax.toml", "[grid\nvoxel_size_mm = 1\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("line 1"));
    }
    SECTION("missing mesh file") {
        const auto s = scene("mesh.toml", kGrid + "[[shape.bag]]\nsource = 'mesh'\nfile = 'absent.obj'\n");
        CHECK_THAT(errorOf(s),
                   Contains(s) && Contains("shape.bag[0].file") && Contains("absent.obj") && Contains("not found"));
    }
    SECTION("flat mesh") {
        const auto obj =
            test::writeText(dir.file("flat.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4\nf 1 4 3\n");
        const auto s = scene("flat.toml", kGrid + "[[shape.bag]]\nsource = 'mesh'\nfile = 'flat.obj'\n");
        CHECK_THAT(errorOf(s), Contains(obj) && Contains("flat"));
    }
    SECTION("fit_voxels beside scale_mm, or without a voxel size") {
        test::writeText(dir.file("tet.obj"),
                        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
        const std::string bag = "[[shape.bag]]\nsource = 'mesh'\nfile = 'tet.obj'\nfit_voxels = 20\n";
        const auto both = scene("both.toml", kGrid + bag + "scale_mm = 2.0\n");
        CHECK_THAT(errorOf(both), Contains(both) && Contains("shape.bag[0].fit_voxels") && Contains("scale_mm"));
        const auto noSize = scene("nosize.toml", "[grid]\n[shape]\n" + bag);
        CHECK_THAT(errorOf(noSize), Contains(noSize) && Contains("fit_voxels") && Contains("voxel_size_mm"));
    }
    SECTION("empty bitmap: a threshold that selects nothing") {
        ScalarImage img;
        img.dims = {8, 8, 8};
        img.spacingMm = Eigen::Vector3d::Ones();
        img.originMm.setZero();
        img.values.assign(img.dims.count(), 1.f);
        writeNifti(dir.file("dim.nii"), img);
        const auto s = scene("empty.toml",
                             "[grid]\n[shape]\n[[shape.bag]]\nsource = 'nifti'\nfile = 'dim.nii'\nthreshold = 2.0\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("shape.bag[0].threshold") && Contains("selects no voxels"));
    }
    SECTION("empty bitmap: an object too small for the voxels") {
        const auto s = scene("tiny.toml",
                             "[grid]\nvoxel_size_mm = 10.0\n[shape]\n[[shape.bag]]\nsource = 'sphere'\nradius_mm = "
                             "6.0\ncenter_mm = [3.0, 3.0, 3.0]\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("shape.bag[0]") && Contains("no object voxels"));
    }
    SECTION("unknown key") {
        const auto s = scene("unknown.toml", kGrid + kSphere + "colour = 'red'\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'shape.bag[0].colour': unknown key"));
    }
    SECTION("unknown top-level table") {
        const auto s = scene("table.toml", kGrid + kSphere + "[physics]\nx = 1\n");  // not a scene table
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'physics': unknown key"));
    }
    SECTION("wrong unit") {
        const auto s = scene("unit.toml", "[grid]\nvoxel_size_cm = 0.1\n[shape]\n" + kSphere);
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'grid.voxel_size_cm'") && Contains("write 'voxel_size_mm'"));
    }
    SECTION("missing unit") {
        const auto s = scene("nounit.toml", kGrid + "[[shape.bag]]\nsource = 'sphere'\nradius = 5.0\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'shape.bag[0].radius_mm': missing"));
    }
    SECTION("wrong type") {
        const auto s = scene("type.toml", "[grid]\nvoxel_size_mm = 1.0\nr0_voxels = 'two'\n[shape]\n" + kSphere);
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'grid.r0_voxels': expected a number, got a string"));
    }
    SECTION("unknown source kind") {
        const auto s = scene("kind.toml", kGrid + "[[shape.bag]]\nsource = 'cube'\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'shape.bag[0].source': 'cube' is not one of"));
    }
    SECTION("negative size") {
        const auto s = scene("neg.toml", kGrid + "[[shape.bag]]\nsource = 'sphere'\nradius_mm = -5.0\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("radius_mm': must be greater than 0"));
    }
    SECTION("an inner bag that is not inside the outer bag") {
        const auto s =
            scene("nest.toml",
                  kGrid + kSphere + "[[shape.bag]]\nsource = 'sphere'\nradius_mm = 3.0\ncenter_mm = [4.0, 0.0, 0.0]\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("shape.bag[1]") && Contains("outside bag"));
    }
    SECTION("an inner bag touching the outer bag's outside") {
        const auto s = scene("touch.toml", kGrid + kSphere + "[[shape.bag]]\nsource = 'sphere'\nradius_mm = 4.9\n");
        CHECK_THAT(errorOf(s), Contains(s) && Contains("shape.bag[1]") && Contains("touches the outside"));
    }
    SECTION("no bags") {
        const auto s = scene("nobag.toml", kGrid);
        CHECK_THAT(errorOf(s), Contains(s) && Contains("'shape.bag': missing"));
    }
}
