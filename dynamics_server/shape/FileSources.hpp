#pragma once
// Model sources backed by files: triangle meshes and segmented volume images.
#include "ImageRasterizer.hpp"
#include "ModelSource.hpp"
#include "ScalarImage.hpp"

#include <memory>
#include <string>
#include <vector>

namespace bop::shape {

// How a mesh's file units become mm: either a fixed scale or a fit to a number of voxels.
struct MeshPlacement {
    double scaleMm = 1.0;  // mm per file unit (fitVoxels == 0)
    int fitVoxels = 0;     // > 0: scale so that the longest side of the bounds spans this many voxels
    double voxelMm = 0;    // voxel edge for fitVoxels, mm
    Eigen::Vector3d offsetMm = Eigen::Vector3d::Zero();  // added after scaling, mm
};

// A mesh from any format loadMesh reads, mended by repairMesh: a closed one is voxelized by
// signed ray crossings (exact), any other (holes, open patches, non-manifold edges) by its
// generalized winding number. warning() names what was found and mended.
// Throws bop::Error naming the file if it is missing or unreadable, flat (its thinnest side
// under 1e-6 of its longest) or closed around no volume.
std::unique_ptr<ModelSource> makeMeshSource(const std::string& path, const MeshPlacement& placement);

// One or more frames of a segmented image; `sel` picks the object voxels.
std::unique_ptr<ModelSource> makeImageSource(std::vector<ScalarImage> frames, const ImageSelect& sel,
                                             const std::string& description);

}  // namespace bop::shape
