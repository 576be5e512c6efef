// Tests of mesh loading through Assimp (OBJ, ASCII/binary STL, PLY, OFF, glTF and GLB), its
// errors, and voxelization of closed meshes by signed ray crossings.
#include "MeshTestUtil.hpp"
#include "bop/common/Error.hpp"
#include "shape/MeshRepair.hpp"
#include "shape/MeshVoxelizer.hpp"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>

using namespace bop;
using namespace bop::shape;
using namespace bop::test;
namespace fs = std::filesystem;

namespace {

// Writes the mesh through Assimp's exporter (format id "gltf2" or "glb2") under a node that
// moves it by `shift`: the reader must apply node transforms.
void exportThroughAssimp(const TriangleMesh& mesh, const std::string& format, const std::string& path,
                         const Eigen::Vector3d& shift) {
    aiScene scene;
    scene.mRootNode = new aiNode();
    scene.mRootNode->mTransformation = aiMatrix4x4();
    scene.mRootNode->mTransformation.a4 = float(shift.x());
    scene.mRootNode->mTransformation.b4 = float(shift.y());
    scene.mRootNode->mTransformation.c4 = float(shift.z());
    scene.mMaterials = new aiMaterial* [1] { new aiMaterial() };
    scene.mNumMaterials = 1;
    auto* m = new aiMesh();
    m->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    m->mNumVertices = unsigned(mesh.vertices.size());
    m->mVertices = new aiVector3D[mesh.vertices.size()];
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        m->mVertices[v] =
            aiVector3D(float(mesh.vertices[v].x()), float(mesh.vertices[v].y()), float(mesh.vertices[v].z()));
    m->mNumFaces = unsigned(mesh.triangles.size());
    m->mFaces = new aiFace[mesh.triangles.size()];
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        m->mFaces[t].mNumIndices = 3;
        m->mFaces[t].mIndices = new unsigned[3]{unsigned(mesh.triangles[t][0]), unsigned(mesh.triangles[t][1]),
                                                unsigned(mesh.triangles[t][2])};
    }
    scene.mMeshes = new aiMesh* [1] { m };
    scene.mNumMeshes = 1;
    scene.mRootNode->mMeshes = new unsigned[1]{0};
    scene.mRootNode->mNumMeshes = 1;
    Assimp::Exporter exporter;
    REQUIRE(exporter.Export(&scene, format, path) == AI_SUCCESS);
}

}  // namespace

TEST_CASE("shipped torus.obj loads, is closed and has the analytic volume", "[shape][mesh]") {
    TriangleMesh mesh = loadMesh(torusPath());
    CHECK(mesh.vertices.size() == 128 * 64);
    CHECK(mesh.triangles.size() == 2 * 128 * 64);
    const MeshRepair repair = repairMesh(mesh);
    CHECK(repair.closed);
    CHECK(repair.summary().empty());
    CHECK(repair.components == 1);
    const double volume = signedVolume(mesh);
    CHECK(volume > 0.0);  // outward orientation
    CHECK(std::abs(volume - kTorusVolumeMm3) < 0.005 * kTorusVolumeMm3);
    CHECK(repair.volume == Approx(volume).epsilon(1e-9));
    const Eigen::AlignedBox3d box = meshBounds(mesh);
    CHECK(box.max().x() == Approx(kMajorMm + kMinorMm).epsilon(0.002));
    CHECK(box.max().z() == Approx(kMinorMm).epsilon(0.002));
    CHECK(box.min().z() == Approx(-kMinorMm).epsilon(0.002));
}

TEST_CASE("torus voxelized at 1 mm matches the analytic torus", "[shape][voxelize]") {
    const TriangleMesh mesh = loadMesh(torusPath());
    const VoxelGrid grid = gridAround(mesh, 1.0, 2);
    Mask mask;
    voxelizeMesh(mesh, grid, mask);
    REQUIRE(mask.dims == grid.dims);
    const std::size_t count = countSet(mask);
    CHECK(std::abs(double(count) - kTorusVolumeMm3) < 0.02 * kTorusVolumeMm3);

    std::size_t disagree = 0;
    for (int k = 0; k < grid.dims.nz; ++k)
        for (int j = 0; j < grid.dims.ny; ++j)
            for (int i = 0; i < grid.dims.nx; ++i) {
                const Eigen::Vector3d p = grid.centreMm(i, j, k);
                const double ring = std::hypot(p.x(), p.y()) - kMajorMm;
                const bool inside = ring * ring + p.z() * p.z() < kMinorMm * kMinorMm;
                disagree += inside != (mask(i, j, k) != 0);
            }
    INFO("object voxels " << count << ", disagreeing voxels " << disagree);
    CHECK(double(disagree) < 0.01 * double(count));
    std::size_t inPadding = 0;  // object voxels in the bottom and top layers
    for (int j = 0; j < grid.dims.ny; ++j)
        for (int i = 0; i < grid.dims.nx; ++i) inPadding += mask(i, j, 0) + mask(i, j, grid.dims.nz - 1);
    CHECK(inPadding == 0);
}

TEST_CASE("STL, PLY, OFF, glTF and GLB load to the same voxelization as the OBJ", "[shape][mesh][voxelize]") {
    const TriangleMesh obj = loadMesh(torusPath());
    const VoxelGrid grid = gridAround(obj, 1.0, 2);
    Mask expected;
    voxelizeMesh(obj, grid, expected);

    TempDir dir("mesh");
    const Eigen::Vector3d shift(5.0, -3.0, 2.0);  // mm: the glTF node's translation
    writeAsciiStl(obj, dir.file("torus-ascii.stl"));
    writeBinaryStl(obj, dir.file("torus-binary.STL"));  // upper-case extension on purpose
    writeAsciiPly(obj, dir.file("torus.ply"));
    writeOff(obj, dir.file("torus.off"));
    exportThroughAssimp(obj, "gltf2", dir.file("torus.gltf"), shift);
    exportThroughAssimp(obj, "glb2", dir.file("torus.glb"), shift);
    for (const std::string name :
         {"torus-ascii.stl", "torus-binary.STL", "torus.ply", "torus.off", "torus.gltf", "torus.glb"}) {
        INFO(name);
        TriangleMesh mesh = loadMesh(dir.file(name));
        CHECK(mesh.triangles.size() == obj.triangles.size());
        CHECK(mesh.vertices.size() == obj.vertices.size());  // welded back to shared vertices
        const bool moved = name.find("gl") != std::string::npos;
        if (moved)
            for (auto& v : mesh.vertices) v -= shift;
        CHECK(repairMesh(mesh).closed);
        Mask mask;
        voxelizeMesh(mesh, grid, mask);
        const std::size_t differ = std::inner_product(mask.data.begin(), mask.data.end(), expected.data.begin(),
                                                      std::size_t(0), std::plus<>(), std::not_equal_to<>());
        // Single-precision files: the same voxels; the moved ones may differ where a face passes a
        // centre within the rounding of the shift.
        CHECK(differ <= (moved ? countSet(expected) / 1000 : 0));
    }
}

TEST_CASE("loadMesh reports missing and malformed files with their path", "[shape][mesh]") {
    TempDir dir("mesh");
    const std::string missing = dir.file("no-such-mesh.obj");
    CHECK_THAT(errorMessage([&] { loadMesh(missing); }), Catch::Contains(missing) && Catch::Contains("not found"));
    try {
        loadMesh(missing);
    } catch (const Error& e) {
        CHECK(e.where() == missing);
    }

    const std::string unknown = dir.file("mesh.xyzzy");
    std::ofstream(unknown) << "ply\n";
    CHECK_THAT(errorMessage([&] { loadMesh(unknown); }), Catch::Contains(unknown) && Catch::Contains(".xyzzy") &&
                                                             Catch::Contains("*.ply") && Catch::Contains("*.glb"));

    const std::string empty = dir.file("empty.obj");
    std::ofstream(empty) << "# nothing\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    CHECK_THAT(errorMessage([&] { loadMesh(empty); }), Catch::Contains(empty) && Catch::Contains("no triangles"));

    const std::string outOfRange = dir.file("range.obj");
    std::ofstream(outOfRange) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
    CHECK_THAT(errorMessage([&] { loadMesh(outOfRange); }), Catch::Contains(outOfRange) && Catch::Contains("range"));

    const std::string badNumber = dir.file("number.obj");
    std::ofstream(badNumber) << "v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n";
    CHECK_THAT(errorMessage([&] { loadMesh(badNumber); }),
               Catch::Contains(badNumber) && Catch::Contains("line 3") && Catch::Contains("v 0 one 0"));

    const std::string badAscii = dir.file("bad.stl");
    std::ofstream(badAscii) << "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zero\n";
    CHECK_THAT(errorMessage([&] { loadMesh(badAscii); }),
               Catch::Contains(badAscii) && Catch::Contains("cannot read") && Catch::Contains("zero"));

    const std::string truncated = dir.file("truncated.stl");
    writeBinaryStl(boxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), truncated);
    fs::resize_file(truncated, 84 + 50 * 12 - 10);
    CHECK_THAT(errorMessage([&] { loadMesh(truncated); }),
               Catch::Contains(truncated) && Catch::Contains("binary STL") && Catch::Contains("674 bytes") &&
                   Catch::Contains("12 triangles"));

    const std::string folder = dir.file("folder.obj");
    fs::create_directory(folder);
    CHECK_THAT(errorMessage([&] { loadMesh(folder); }), Catch::Contains(folder) && Catch::Contains("directory"));
}

TEST_CASE("cube voxelization gives exact counts with centres on or between face planes", "[shape][voxelize]") {
    const TriangleMesh cube = boxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(10.0));  // 10 mm cube
    REQUIRE(cube.triangles.size() == 12);
    REQUIRE(signedVolume(cube) == Approx(1000.0));

    // Expected: centres c with 0 <= c < 10 on every axis (a centre on a face counts as moved by +tiny).
    const auto check = [&](const VoxelGrid& grid, std::size_t expectedCount) {
        Mask mask;
        voxelizeMesh(cube, grid, mask);
        std::size_t wrong = 0;
        for (int k = 0; k < grid.dims.nz; ++k)
            for (int j = 0; j < grid.dims.ny; ++j)
                for (int i = 0; i < grid.dims.nx; ++i) {
                    const Eigen::Vector3d p = grid.centreMm(i, j, k);
                    const bool inside = (p.array() >= 0.0).all() && (p.array() < 10.0).all();
                    wrong += inside != (mask(i, j, k) != 0);
                }
        CHECK(countSet(mask) == expectedCount);
        CHECK(wrong == 0);
    };
    VoxelGrid grid;
    SECTION("centres exactly on the face planes") {
        grid = {{17, 17, 17}, Eigen::Vector3d::Constant(-3.5), 1.0};  // centres at -3, -2, ..., 13 mm
        check(grid, 1000);
    }
    SECTION("faces halfway between centres") {
        grid = {{16, 16, 16}, Eigen::Vector3d::Constant(-3.0), 1.0};  // centres at -2.5, ..., 12.5 mm
        check(grid, 1000);
    }
    SECTION("half-millimetre voxels, faces between centres") {
        grid = {{24, 24, 24}, Eigen::Vector3d::Constant(-1.0), 0.5};  // centres at -0.75, -0.25, 0.25, ...
        check(grid, 8000);
    }
    SECTION("quarter-millimetre voxels, centres on the planes, grid cutting the cube") {
        grid = {{30, 50, 60}, Eigen::Vector3d(-2.125, 4.875, -5.125), 0.25};  // centres at multiples of 0.125
        // centres in [0, 10): x -2.0 .. 5.25 -> 0 .. 5.25 (22); y 5.0 .. 17.25 -> 5.0 .. 9.75 (20);
        // z -5.0 .. 9.75 -> 0 .. 9.75 (40)
        check(grid, 22 * 20 * 40);
    }
}
