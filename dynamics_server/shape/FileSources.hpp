#pragma once
// Model sources backed by files: closed triangle meshes and segmented volume images.
#include "ImageRasterizer.hpp"
#include "ModelSource.hpp"
#include "ScalarImage.hpp"

#include <memory>
#include <string>
#include <vector>

namespace bop::shape {

// A closed mesh (OBJ or STL); vertices are scaled by scaleMm (mm per file unit) then shifted.
// Throws bop::Error naming the file if it is missing, unreadable or not closed.
std::unique_ptr<ModelSource> makeMeshSource(const std::string& path, double scaleMm, const Eigen::Vector3d& offsetMm);

// One or more frames of a segmented image; `sel` picks the object voxels.
std::unique_ptr<ModelSource> makeImageSource(std::vector<ScalarImage> frames, const ImageSelect& sel,
                                             const std::string& description);

}  // namespace bop::shape
