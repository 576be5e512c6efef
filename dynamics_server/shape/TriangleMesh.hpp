#pragma once
// Triangle surface meshes loaded from OBJ or STL files, with the topology check that
// voxelization by ray parity relies on (a closed, consistently oriented surface).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace bop::shape {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> vertices;      // vertex positions, mm
    std::vector<std::array<int, 3>> triangles;  // vertex indices (0-based), counter-clockwise seen from outside
};

// Loads a mesh, choosing the format by extension (case-insensitive):
//   .obj  Wavefront OBJ (polygons are triangulated; coordinates read as single precision),
//   .stl  binary or ASCII STL (identical vertex coordinates are welded into one vertex).
// path: file path; coordinates are taken as millimetres.
// Throws bop::Error(path, ...) for a missing or unreadable file, an unknown extension,
// a parse error, a mesh without triangles or a vertex index out of range.
TriangleMesh loadMesh(const std::string& path);

// Requires a closed (watertight) surface: every undirected edge of a non-degenerate
// triangle is used by exactly two triangles, once in each direction (consistent
// orientation). Zero-area triangles are ignored. path: named in the error message only.
// Throws bop::Error(path, "mesh is not closed: ...") otherwise.
void requireClosed(const TriangleMesh& mesh, const std::string& path);

// Axis-aligned bounds of the vertices used by triangles, mm (empty box if none).
Eigen::AlignedBox3d meshBounds(const TriangleMesh& mesh);

}  // namespace bop::shape
