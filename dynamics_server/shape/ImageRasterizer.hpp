#pragma once
// Turns a scalar image (segmentation labels or intensities) into an object mask on a cubic
// voxel grid by nearest-sample lookup: each grid voxel takes the image voxel containing its
// centre. When the grid has the image's (isotropic) spacing and its origin is offset from the
// image origin by a whole number of voxels, the mask is an exact copy of the selection, padded.
#include "ScalarImage.hpp"
#include "bop/common/Volume.hpp"

#include <Eigen/Geometry>

#include <cstddef>
#include <vector>

namespace bop::shape {

// Which image voxels belong to the object.
struct ImageSelect {
    enum class Mode { Threshold, Label } mode = Mode::Threshold;  // test applied to each value
    double threshold = 0.5;  // object where value >= threshold (image units); Threshold mode
    std::vector<double> labels{
        1};  // object where value equals one of them (image units, compared as float); Label mode
};

// True when `value` belongs to the object under `sel` (NaN never does).
bool isSelected(float value, const ImageSelect& sel);

// Box covered by the image: originMm to originMm + dims * spacingMm, mm.
Eigen::AlignedBox3d imageBounds(const ScalarImage& img);

// Fills `out` (resized to grid.dims) with 1 where the image voxel containing the grid voxel
// centre is selected, 0 elsewhere, including centres outside the image.
void rasterizeImage(const ScalarImage& img, const ImageSelect& sel, const VoxelGrid& grid, Mask& out);

// Number of image voxels selected by `sel`.
std::size_t countSelected(const ScalarImage& img, const ImageSelect& sel);

}  // namespace bop::shape
