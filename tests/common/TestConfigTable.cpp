// The config reader: typed access, defaults, and errors that name the file and the key.
#include "TestUtil.hpp"
#include "bop/common/ConfigTable.hpp"

#include <catch2/catch.hpp>

using namespace bop;

TEST_CASE("config tables read typed values with defaults", "[config]") {
    const toml::table doc = toml::parse("a_mm = 2\nb = 'x'\nv_mm = [1, 2.5, 3]\n[t]\nk = true\n");
    const ConfigTable root(doc, "scene.toml", "");
    CHECK(root.number("a_mm") == 2.0);
    CHECK(root.number("missing_mm", 7.5) == 7.5);
    CHECK(root.string("b") == "x");
    CHECK(root.vec3("v_mm") == Eigen::Vector3d(1, 2.5, 3));
    CHECK(root.table("t").boolean("k", false));
    CHECK_NOTHROW(root.finish());
}

TEST_CASE("config errors name the file and the key and say what was expected", "[config]") {
    const toml::table doc = toml::parse("[grid]\nvoxel_size_cm = 2\nr0_voxels = 'two'\n");
    const ConfigTable root(doc, "scenes/x.toml", "");
    const ConfigTable grid = root.table("grid");
    CHECK(test::errorMessage([&] { grid.number("r0_voxels"); }) ==
          "scenes/x.toml: key 'grid.r0_voxels': expected a number, got a string");
    CHECK(test::errorMessage([&] { grid.number("padding_voxels"); }).find("'grid.padding_voxels': missing") !=
          std::string::npos);
    (void)grid.has("voxel_size_mm");
    CHECK(test::errorMessage([&] { grid.finish(); }) ==
          "scenes/x.toml: key 'grid.voxel_size_cm': unit 'cm' is not accepted here; this quantity is in "
          "millimetres: write 'voxel_size_mm'");
    const toml::table doc2 = toml::parse("size = 3\n");
    const ConfigTable t2(doc2, "y.toml", "");
    (void)t2.has("size_voxels");
    CHECK(test::errorMessage([&] {
              t2.finish();
          }).find("key 'size': the unit is missing; this quantity is in voxels") != std::string::npos);
    const toml::table doc3 = toml::parse("speed = 1\n");
    const ConfigTable t3(doc3, "z.toml", "");
    (void)t3.has("voxel_size_mm");
    CHECK(test::errorMessage([&] { t3.finish(); }) ==
          "z.toml: key 'speed': unknown key (known keys here: voxel_size_mm)");
    CHECK(test::errorMessage([&] {
              t3.choice("speed", {"a", "b"}, "a");
          }).find("expected a string") != std::string::npos);
}

TEST_CASE("a missing or malformed TOML file is reported with its path and line", "[config]") {
    CHECK(test::errorMessage([] { ConfigTable::parseFile("/nonexistent/scene.toml"); }) ==
          "/nonexistent/scene.toml: file not found (expected a TOML scene file)");
}
