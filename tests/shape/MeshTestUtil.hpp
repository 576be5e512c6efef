#pragma once
// Meshes for the mesh tests: analytic solids as triangles, writers of the formats users bring
// (OBJ, ASCII and binary STL, ASCII PLY, OFF), and the torus shipped in config/models.
#include "TestUtil.hpp"
#include "bop/common/Volume.hpp"
#include "shape/TriangleMesh.hpp"

#include <string>

namespace bop::test {

constexpr double kMajorMm = 30.0;  // torus.obj major radius R, mm
constexpr double kMinorMm = 12.0;  // torus.obj minor radius r, mm
inline const double kTorusVolumeMm3 = 2.0 * M_PI * M_PI * kMajorMm * kMinorMm * kMinorMm;

std::string torusPath();  // config/models/torus.obj

// Signed volume by the divergence theorem, mm^3 (positive for outward orientation).
double signedVolume(const shape::TriangleMesh& mesh);
// Grid of voxelMm voxels around the mesh bounds with padVoxels empty voxels on each side.
VoxelGrid gridAround(const shape::TriangleMesh& mesh, double voxelMm, int padVoxels);
std::size_t countSet(const Mask& mask);

// Axis-aligned box [lo, hi] mm as 12 triangles, counter-clockwise seen from outside.
shape::TriangleMesh boxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);
// Sphere of `radius` mm about `centre` as a latitude-longitude mesh of `rings` x 2 rings
// triangles, outward; vertices on the sphere.
shape::TriangleMesh sphereMesh(const Eigen::Vector3d& centre, double radius, int rings);
// Both meshes in one (indices of b shifted).
shape::TriangleMesh joined(const shape::TriangleMesh& a, const shape::TriangleMesh& b);

void writeObj(const shape::TriangleMesh& mesh, const std::string& path);
void writeAsciiStl(const shape::TriangleMesh& mesh, const std::string& path);
// Binary STL whose header deliberately starts with "solid", as some exporters write.
void writeBinaryStl(const shape::TriangleMesh& mesh, const std::string& path);
void writeAsciiPly(const shape::TriangleMesh& mesh, const std::string& path);
void writeOff(const shape::TriangleMesh& mesh, const std::string& path);

}  // namespace bop::test
