#pragma once
// Triangle surface meshes read from the files users bring (OBJ, STL, PLY, OFF, glTF/GLB and the
// other formats of Debian's Assimp), welded into one indexed triangle list.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace bop::shape {

struct TriangleMesh {
    std::vector<Eigen::Vector3d> vertices;      // vertex positions, file units (mm once scaled)
    std::vector<std::array<int, 3>> triangles;  // vertex indices (0-based), counter-clockwise seen from outside
};

// Loads every triangle of every mesh in a file through Assimp (polygons triangulated, node
// transforms applied, points and lines left out) and welds corners with identical coordinates
// into one vertex, so that the topology can be checked. Coordinates are single precision as
// Assimp reads them. path: the file; its extension picks the format (case-insensitive).
// Throws bop::Error(path, ...) for a missing or unreadable file, a format Assimp does not read
// (naming the accepted extensions), a parse error (with Assimp's reason), an OBJ vertex line
// without three finite numbers (naming its line), a non-finite coordinate or no triangles.
TriangleMesh loadMesh(const std::string& path);

// Axis-aligned bounds of the vertices used by triangles (empty box if none), vertex units.
Eigen::AlignedBox3d meshBounds(const TriangleMesh& mesh);

}  // namespace bop::shape
