// Meshes as a person sees them: the generalized winding number against analytic solids with
// punched holes, flipped patches, inside-out and overlapping parts; what repairMesh mends and
// reports; flat and empty meshes refused.
#include "MeshTestUtil.hpp"
#include "shape/FileSources.hpp"
#include "shape/MeshRepair.hpp"
#include "shape/MeshVoxelizer.hpp"
#include "shape/WindingNumber.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace bop;
using namespace bop::shape;
using namespace bop::test;

namespace {

constexpr double kRadiusMm = 10.0;  // test sphere radius, mm

// Drops the triangles whose centroid lies within `reach` mm of any of `centres`.
TriangleMesh punched(TriangleMesh mesh, const std::vector<Eigen::Vector3d>& centres, double reach) {
    std::erase_if(mesh.triangles, [&](const std::array<int, 3>& t) {
        const Eigen::Vector3d c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
        for (const auto& x : centres)
            if ((c - x).norm() < reach) return true;
        return false;
    });
    return mesh;
}

// Voxels of the mask that disagree with `inside` at their centres.
std::size_t disagreement(const Mask& mask, const VoxelGrid& grid,
                         const std::function<bool(const Eigen::Vector3d&)>& inside) {
    std::size_t wrong = 0;
    for (int k = 0; k < grid.dims.nz; ++k)
        for (int j = 0; j < grid.dims.ny; ++j)
            for (int i = 0; i < grid.dims.nx; ++i) wrong += inside(grid.centreMm(i, j, k)) != (mask(i, j, k) != 0);
    return wrong;
}

bool inSphere(const Eigen::Vector3d& p) {
    return p.norm() < kRadiusMm;
}

}  // namespace

TEST_CASE("the winding-number tree agrees with the exact sum over triangles", "[shape][winding]") {
    const TriangleMesh mesh = punched(sphereMesh(Eigen::Vector3d::Zero(), kRadiusMm, 40),
                                      {Eigen::Vector3d(0, 0, kRadiusMm), Eigen::Vector3d(kRadiusMm, 0, 0)}, 4.0);
    const WindingNumber w(mesh);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> coord(-1.6 * kRadiusMm, 1.6 * kRadiusMm);
    double worst = 0;
    int otherSide = 0;  // the tree puts q on the other side of 1/2 though the exact w is 0.03 away from it
    for (int n = 0; n < 2000; ++n) {
        const Eigen::Vector3d q(coord(rng), coord(rng), coord(rng));
        const double tree = w.at(q), exact = w.exactAt(q);
        worst = std::max(worst, std::abs(tree - exact));
        otherSide += (tree >= 0.5) != (exact >= 0.5) && std::abs(exact - 0.5) > 0.03;
    }
    INFO("largest difference " << worst);
    CHECK(worst < 0.03);  // first-order far field at 2.5 node radii
    CHECK(otherSide == 0);
    // Far inside and far outside a closed sphere: 1 and 0.
    const WindingNumber closed(sphereMesh(Eigen::Vector3d::Zero(), kRadiusMm, 40));
    CHECK(closed.exactAt(Eigen::Vector3d(1, 2, 3)) == Approx(1.0).margin(1e-12));
    CHECK(closed.at(Eigen::Vector3d(1, 2, 3)) == Approx(1.0).margin(0.03));
    CHECK(closed.at(Eigen::Vector3d(30, 2, 3)) == Approx(0.0).margin(0.03));
    CHECK(closed.exactAt(Eigen::Vector3d(30, 2, 3)) == Approx(0.0).margin(1e-12));
}

TEST_CASE("a sphere with punched holes voxelizes to the sphere", "[shape][winding][voxelize]") {
    TriangleMesh mesh = punched(sphereMesh(Eigen::Vector3d::Zero(), kRadiusMm, 48),
                                {Eigen::Vector3d(0, 0, kRadiusMm), Eigen::Vector3d(0, -kRadiusMm, 0),
                                 Eigen::Vector3d(0.6, 0.6, 0.529).normalized() * kRadiusMm},
                                3.0);
    const MeshRepair repair = repairMesh(mesh);
    CHECK_FALSE(repair.closed);
    CHECK(repair.boundaryEdges > 30);
    CHECK(repair.nonManifoldEdges == 0);
    CHECK(repair.flipped == 0);
    CHECK_FALSE(repair.turnedOut);
    CHECK_THAT(repair.summary(), Catch::Contains(std::to_string(repair.boundaryEdges) + " boundary edges") &&
                                     Catch::Contains("winding number"));

    const VoxelGrid grid = gridAround(mesh, 0.5, 3);
    Mask byWinding, byRays;
    voxelizeByWindingNumber(WindingNumber(mesh), grid, byWinding);
    const std::size_t count = countSet(byWinding);
    const double sphere = 4.0 / 3.0 * M_PI * std::pow(kRadiusMm / 0.5, 3);  // voxels
    INFO("winding-number voxels " << count << ", sphere " << sphere);
    CHECK(std::abs(double(count) - sphere) < 0.02 * sphere);
    CHECK(disagreement(byWinding, grid, inSphere) < count / 100);
    // Ray crossings cannot see through the holes: the same mesh counted by rays loses voxels
    // along the rays that pass a hole (the test can tell the two apart).
    voxelizeMesh(mesh, grid, byRays);
    CHECK(disagreement(byRays, grid, inSphere) > 2 * disagreement(byWinding, grid, inSphere));
}

TEST_CASE("flipped patches and an inside-out mesh are turned and voxelize as the original", "[shape][winding]") {
    const TriangleMesh original = sphereMesh(Eigen::Vector3d::Zero(), kRadiusMm, 24);
    const VoxelGrid grid = gridAround(original, 0.5, 2);
    Mask expected;
    voxelizeMesh(original, grid, expected);

    SECTION("a cap stored the other way round") {
        TriangleMesh mesh = original;
        std::size_t cap = 0;
        for (auto& t : mesh.triangles)
            if ((mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]).z() > 3 * 0.6 * kRadiusMm) {
                std::swap(t[0], t[1]);
                ++cap;
            }
        REQUIRE(cap > 10);
        const MeshRepair repair = repairMesh(mesh);
        CHECK(repair.flipped == cap);
        CHECK(repair.closed);
        CHECK_THAT(repair.summary(), Catch::Contains(std::to_string(cap) + " triangles turned"));
        Mask mask;
        voxelizeMesh(mesh, grid, mask);
        CHECK(mask.data == expected.data);
    }
    SECTION("the whole mesh inside out") {
        TriangleMesh mesh = original;
        for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
        const MeshRepair repair = repairMesh(mesh);
        CHECK(repair.turnedOut);
        CHECK(repair.flipped == 0);
        CHECK(repair.volume > 0);
        Mask mask;
        voxelizeMesh(mesh, grid, mask);
        CHECK(mask.data == expected.data);
    }
}

TEST_CASE("overlapping closed parts voxelize to their union", "[shape][winding][voxelize]") {
    // Two 10 mm cubes overlapping by half: ray parity would leave the overlap out.
    TriangleMesh mesh = joined(boxMesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(10, 10, 10)),
                               boxMesh(Eigen::Vector3d(5, 0, 0), Eigen::Vector3d(15, 10, 10)));
    const MeshRepair repair = repairMesh(mesh);
    CHECK(repair.closed);
    CHECK(repair.components == 2);
    const VoxelGrid grid{{19, 14, 14}, Eigen::Vector3d(-2, -2, -2), 1.0};  // faces halfway between centres
    Mask byRays, byWinding;
    voxelizeMesh(mesh, grid, byRays);
    CHECK(countSet(byRays) == 15 * 10 * 10);
    voxelizeByWindingNumber(WindingNumber(mesh), grid, byWinding);
    CHECK(byWinding.data == byRays.data);
}

TEST_CASE("repairMesh counts non-manifold edges and pieces and drops zero-area triangles", "[shape][winding]") {
    TriangleMesh fan;
    fan.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {2, 2, 2}, {3, 3, 3}};
    fan.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {5, 6, 5}, {0, 5, 6}};  // three share edge 0-1
    const MeshRepair repair = repairMesh(fan);
    CHECK(repair.nonManifoldEdges == 1);
    CHECK(repair.degenerate == 2);  // a repeated vertex; three collinear corners
    CHECK(repair.triangles == 3);
    CHECK(repair.components == 1);
    CHECK_FALSE(repair.closed);
}

TEST_CASE("flat meshes and meshes around no volume are refused naming the file", "[shape][winding][errors]") {
    TempDir dir("flat");
    TriangleMesh square;
    square.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    square.triangles = {{0, 1, 2}, {0, 2, 3}};
    writeObj(square, dir.file("square.obj"));
    CHECK_THAT(errorMessage([&] { makeMeshSource(dir.file("square.obj"), {}); }),
               Catch::Contains(dir.file("square.obj")) && Catch::Contains("flat"));

    // Two closed "pillows" (a square and its reverse) in perpendicular planes: 3D bounds, no volume.
    TriangleMesh pillows;
    pillows.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}};
    pillows.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {4, 6, 5}, {4, 7, 6}};
    writeObj(pillows, dir.file("pillows.obj"));
    CHECK_THAT(errorMessage([&] { makeMeshSource(dir.file("pillows.obj"), {}); }),
               Catch::Contains(dir.file("pillows.obj")) && Catch::Contains("no volume"));
}

TEST_CASE("a torus with a missing triangle voxelizes as the closed torus", "[shape][winding][voxelize]") {
    TriangleMesh closed = loadMesh(torusPath());
    TriangleMesh holed = closed;
    holed.triangles.erase(holed.triangles.begin() + 1000);
    const MeshRepair repair = repairMesh(holed);
    CHECK(repair.boundaryEdges == 3);
    CHECK_FALSE(repair.closed);
    const VoxelGrid grid = gridAround(closed, 1.0, 2);
    Mask expected, mask;
    voxelizeMesh(closed, grid, expected);
    voxelizeByWindingNumber(WindingNumber(holed), grid, mask);
    std::size_t differ = 0;
    for (std::size_t v = 0; v < mask.data.size(); ++v) differ += mask.data[v] != expected.data[v];
    INFO(differ << " of " << countSet(expected) << " voxels differ");
    CHECK(differ <= countSet(expected) / 1000);
}
