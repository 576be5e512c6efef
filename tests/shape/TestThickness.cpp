// Thin parts (shape/Thickness.hpp): a plate 3 voxels thick beside a ball 17 voxels across, at
// r0 = 2 voxels (a part must be 4 across): the plate's voxels are the thin ones, the ball's not.
#include "shape/ShapeTestUtil.hpp"
#include "shape/Thickness.hpp"

#include <catch2/catch.hpp>

using namespace bop;

TEST_CASE("the plate is found thin and the ball is not", "[shape][thickness]") {
    const Dims d{60, 34, 34};
    const auto plate = [](const Eigen::Vector3d& x) {
        return x.x() > 4 && x.x() < 28 && x.y() > 4 && x.y() < 28 && x.z() > 10 && x.z() < 13;
    };
    const Eigen::Vector3d c(44, 17, 17);
    const auto ball = [&](const Eigen::Vector3d& x) { return (x - c).norm() < 8.5; };
    std::size_t plateVoxels = 0, ballVoxels = 0;
    for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
            for (int x = 0; x < d.nx; ++x) {
                const Eigen::Vector3d p(x + 0.5, y + 0.5, z + 0.5);
                plateVoxels += plate(p);
                ballVoxels += ball(p);
            }
    REQUIRE(plateVoxels == 24 * 24 * 3);

    const GradientMap both =
        test::mapFrom(test::depthFrom(d, {[&](const Eigen::Vector3d& x) { return plate(x) || ball(x); }}), 2.0, 1.5);
    const shape::ThinParts t = shape::findThinParts(both, 1, 2 * both.r0Voxels);
    INFO(t.thinVoxels << " thin of " << t.bagVoxels << "; the thinnest " << t.thinnestVoxels << " voxels across");
    CHECK(t.bagVoxels == plateVoxels + ballVoxels);
    CHECK(t.thinnestVoxels == Approx(3.0));
    CHECK(t.thinVoxels >= std::size_t(0.95 * double(plateVoxels)));
    CHECK(t.thinVoxels <= plateVoxels);
    const std::string w = shape::thinPartsWarning("slab", t, both.r0Voxels);
    CHECK_THAT(w, Catch::Contains("bag 'slab'") && Catch::Contains("thinnest is 3 voxels across (1.50 r0)") &&
                      Catch::Contains("r0_voxels = 1.5"));

    const GradientMap alone = test::mapFrom(test::depthFrom(d, {ball}), 2.0, 1.5);
    const shape::ThinParts b = shape::findThinParts(alone, 1, 2 * alone.r0Voxels);
    CHECK(b.thinVoxels == 0);
    // 17 across, centred on a voxel corner: its deepest voxel centres lie 7.7 from the nearest
    // voxel outside, 14.4 across by the plate's rule; within the voxel steps of 17.
    CHECK(b.thinnestVoxels >= 14.0);
    CHECK(b.thinnestVoxels <= 17.0);
    CHECK(shape::thinPartsWarning("ball", b, alone.r0Voxels).empty());
}
