// Tests of mesh loading (OBJ, ASCII/binary STL), the closedness check and voxelization.
#include "TestUtil.hpp"
#include "bop/common/Error.hpp"
#include "shape/MeshVoxelizer.hpp"
#include "shape/TriangleMesh.hpp"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>

#ifndef BOP_SOURCE_DIR
#define BOP_SOURCE_DIR "/work/main"
#endif

using namespace bop;
using namespace bop::shape;
namespace fs = std::filesystem;

namespace {

constexpr double kMajorMm = 30.0;  // torus major radius R, mm
constexpr double kMinorMm = 12.0;  // torus minor radius r, mm
const double kTorusVolumeMm3 = 2.0 * M_PI * M_PI * kMajorMm * kMinorMm * kMinorMm;

std::string torusPath() {
    return bop::test::sourceDir() + "/config/models/torus.obj";
}

// Signed volume by the divergence theorem, mm^3 (positive for outward orientation).
double signedVolume(const TriangleMesh& mesh) {
    double sixTimes = 0.0;
    for (const auto& t : mesh.triangles)
        sixTimes += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
    return sixTimes / 6.0;
}

// Grid of voxelMm voxels around the mesh bounds with padVoxels empty voxels on each side.
VoxelGrid gridAround(const TriangleMesh& mesh, double voxelMm, int padVoxels) {
    const Eigen::AlignedBox3d box = meshBounds(mesh);
    VoxelGrid grid;
    grid.voxelMm = voxelMm;
    grid.originMm = box.min() - Eigen::Vector3d::Constant(padVoxels * voxelMm);
    const Eigen::Vector3d extent = box.sizes() / voxelMm;
    grid.dims = {int(std::ceil(extent.x())) + 2 * padVoxels, int(std::ceil(extent.y())) + 2 * padVoxels,
                 int(std::ceil(extent.z())) + 2 * padVoxels};
    return grid;
}

std::size_t countSet(const Mask& mask) {
    std::size_t n = 0;
    for (const auto v : mask.data) n += v != 0;
    return n;
}

void writeObj(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(17);
    for (const auto& p : mesh.vertices) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

Eigen::Vector3d unitNormal(const TriangleMesh& mesh, const std::array<int, 3>& t) {
    const auto& a = mesh.vertices[t[0]];
    return (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).normalized();
}

void writeAsciiStl(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(17);
    out << "solid test mesh\n";
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d n = unitNormal(mesh, t);
        out << "  facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n    outer loop\n";
        for (const int i : t) {
            const auto& p = mesh.vertices[i];
            out << "      vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
        }
        out << "    endloop\n  endfacet\n";
    }
    out << "endsolid test mesh\n";
}

void putLittle32(std::ofstream& out, std::uint32_t value) {
    for (int b = 0; b < 4; ++b) out.put(char((value >> (8 * b)) & 0xffu));
}

// Binary STL whose header deliberately starts with "solid", as some exporters write.
void writeBinaryStl(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path, std::ios::binary);
    std::string header = "solid binary STL written by TestMesh";
    header.resize(80, ' ');
    out.write(header.data(), 80);
    putLittle32(out, std::uint32_t(mesh.triangles.size()));
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d n = unitNormal(mesh, t);
        for (int c = 0; c < 3; ++c) putLittle32(out, std::bit_cast<std::uint32_t>(float(n[c])));
        for (const int i : t)
            for (int c = 0; c < 3; ++c) putLittle32(out, std::bit_cast<std::uint32_t>(float(mesh.vertices[i][c])));
        out.put(0).put(0);  // attribute byte count
    }
}

// Axis-aligned box [lo, hi] mm as 12 triangles, counter-clockwise seen from outside.
TriangleMesh boxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    TriangleMesh mesh;
    for (int c = 0; c < 8; ++c)  // corner c: bit 0 -> x, bit 1 -> y, bit 2 -> z at hi
        mesh.vertices.emplace_back(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    return mesh;
}

std::string errorMessage(const std::function<void()>& action) {
    try {
        action();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no bop::Error thrown)";
}

}  // namespace

TEST_CASE("shipped torus.obj loads, is closed and has the analytic volume", "[shape][mesh]") {
    const TriangleMesh mesh = loadMesh(torusPath());
    CHECK(mesh.vertices.size() == 128 * 64);
    CHECK(mesh.triangles.size() == 2 * 128 * 64);
    CHECK_NOTHROW(requireClosed(mesh, torusPath()));
    const double volume = signedVolume(mesh);
    CHECK(volume > 0.0);  // outward orientation
    CHECK(std::abs(volume - kTorusVolumeMm3) < 0.005 * kTorusVolumeMm3);
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

TEST_CASE("binary and ASCII STL load to the same voxelization as the OBJ", "[shape][mesh][voxelize]") {
    const TriangleMesh obj = loadMesh(torusPath());
    const VoxelGrid grid = gridAround(obj, 1.0, 2);
    Mask expected;
    voxelizeMesh(obj, grid, expected);

    bop::test::TempDir dir("mesh");
    writeAsciiStl(obj, dir.file("torus-ascii.stl"));
    writeBinaryStl(obj, dir.file("torus-binary.STL"));  // upper-case extension on purpose
    for (const std::string& path : {dir.file("torus-ascii.stl"), dir.file("torus-binary.STL")}) {
        INFO(path);
        const TriangleMesh stl = loadMesh(path);
        CHECK(stl.triangles.size() == obj.triangles.size());
        CHECK(stl.vertices.size() == obj.vertices.size());  // welded back to shared vertices
        CHECK_NOTHROW(requireClosed(stl, path));
        Mask mask;
        voxelizeMesh(stl, grid, mask);
        CHECK(mask.data == expected.data);
    }
}

TEST_CASE("a mesh with a missing or flipped triangle is rejected as not closed", "[shape][mesh]") {
    TriangleMesh mesh = loadMesh(torusPath());
    bop::test::TempDir dir("mesh");
    SECTION("one triangle removed") {
        mesh.triangles.erase(mesh.triangles.begin() + 1000);
        const std::string path = dir.file("holed.obj");
        writeObj(mesh, path);
        const TriangleMesh holed = loadMesh(path);
        const std::string message = errorMessage([&] { requireClosed(holed, path); });
        CHECK_THAT(message,
                   Catch::Contains(path) && Catch::Contains("not closed") && Catch::Contains("3 boundary edges"));
    }
    SECTION("one triangle flipped") {
        std::swap(mesh.triangles[7][0], mesh.triangles[7][1]);
        const std::string message = errorMessage([&] { requireClosed(mesh, "flipped.obj"); });
        CHECK_THAT(message, Catch::Contains("flipped.obj") && Catch::Contains("not closed") &&
                                Catch::Contains("3 edges whose two triangles are inconsistently oriented"));
    }
}

TEST_CASE("loadMesh reports missing and malformed files with their path", "[shape][mesh]") {
    bop::test::TempDir dir("mesh");
    const std::string missing = dir.file("no-such-mesh.obj");
    CHECK_THAT(errorMessage([&] { loadMesh(missing); }), Catch::Contains(missing) && Catch::Contains("not found"));
    try {
        loadMesh(missing);
    } catch (const Error& e) {
        CHECK(e.where() == missing);
    }

    const std::string ply = dir.file("mesh.ply");
    std::ofstream(ply) << "ply\n";
    CHECK_THAT(errorMessage([&] { loadMesh(ply); }), Catch::Contains(ply) && Catch::Contains(".obj and .stl"));

    const std::string empty = dir.file("empty.obj");
    std::ofstream(empty) << "# nothing\nv 0 0 0\n";
    CHECK_THAT(errorMessage([&] { loadMesh(empty); }), Catch::Contains(empty) && Catch::Contains("no triangles"));

    const std::string outOfRange = dir.file("range.obj");
    std::ofstream(outOfRange) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
    CHECK_THAT(errorMessage([&] { loadMesh(outOfRange); }), Catch::Contains(outOfRange) && Catch::Contains("range"));

    const std::string badAscii = dir.file("bad.stl");
    std::ofstream(badAscii) << "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zero\n";
    CHECK_THAT(errorMessage([&] { loadMesh(badAscii); }),
               Catch::Contains(badAscii) && Catch::Contains("ASCII STL") && Catch::Contains("line 4"));

    const std::string truncated = dir.file("truncated.stl");
    writeBinaryStl(boxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), truncated);
    fs::resize_file(truncated, 84 + 50 * 12 - 10);
    CHECK_THAT(errorMessage([&] { loadMesh(truncated); }), Catch::Contains(truncated) && Catch::Contains("bytes"));
}

TEST_CASE("cube voxelization gives exact counts with centres on or between face planes", "[shape][voxelize]") {
    const TriangleMesh cube = boxMesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(10.0));  // 10 mm cube
    REQUIRE(cube.triangles.size() == 12);
    REQUIRE_NOTHROW(requireClosed(cube, "cube"));
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
