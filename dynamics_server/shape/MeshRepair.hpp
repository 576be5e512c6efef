#pragma once
// What a mesh from a user's file needs before it can be voxelized, found and mended where it
// can be: zero-area triangles dropped, triangles turned to agree with their neighbours (a patch
// stored the other way round), the whole mesh turned when it is inside out. Holes (boundary
// edges) and non-manifold edges are counted, not filled: the generalized winding number
// (WindingNumber.hpp) gives the solid they bound.
#include "TriangleMesh.hpp"

#include <cstddef>
#include <string>

namespace bop::shape {

struct MeshRepair {
    std::size_t triangles = 0;         // triangles kept
    std::size_t degenerate = 0;        // zero-area triangles dropped
    std::size_t boundaryEdges = 0;     // edges used by one triangle (holes, open patches)
    std::size_t nonManifoldEdges = 0;  // edges used by three or more triangles
    std::size_t flipped = 0;           // triangles turned to agree with their edge neighbours
    std::size_t components = 0;        // pieces connected through shared edges
    bool turnedOut = false;            // the mesh was inside out (negative volume) and was turned
    bool closed = false;  // every edge is used as often in one direction as in the other: ray counting is exact
    double volume = 0;    // signed volume enclosed after the repair, vertex units^3 (open meshes: up to the holes)
    double area = 0;      // surface area, vertex units^2

    // One line for a warning: what was found and what was done, "" for a closed, clean mesh.
    std::string summary() const;
};

// Mends `mesh` in place as described above and reports it.
MeshRepair repairMesh(TriangleMesh& mesh);

}  // namespace bop::shape
