#pragma once
// Scalar voxel images read from NIfTI-1 files or headerless raw files, and a NIfTI-1 writer
// for tests and synthetic data.
//
// Orientation: qform/sform matrices are ignored apart from the voxel spacing (pixdim[1..3],
// absolute value). Every loaded image is placed axis-aligned with the corner of voxel (0,0,0)
// at the model origin, voxel index x fastest, exactly as stored in the file. Images whose
// scanner axes are flipped or oblique are therefore read in storage order, not reoriented.
//
// Values are held as float after applying scl_slope/scl_inter (NIfTI, when the slope is finite
// and nonzero): integer values beyond 2^24 and float64 values lose precision. NaN/inf samples are
// kept as stored. On a bad file niftiio may also print its own message to stderr; the error
// that reaches the caller is always a bop::Error naming the path.
#include "bop/common/Volume.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace bop::shape {

// Which values a reader keeps the box of (ShapeSpec: the bag's selection); empty = the whole image.
using KeepFn = std::function<bool(float)>;

struct ScalarImage {
    Dims dims;                  // voxels per axis
    Eigen::Vector3d spacingMm;  // voxel spacing per axis, mm
    Eigen::Vector3d originMm;   // corner of voxel (0,0,0), mm; for loaded images 0, or the kept box's corner
    std::vector<float> values;  // one value per voxel (image units), x fastest, dims.count() long
};

// Reads a NIfTI-1 image (.nii, .nii.gz, or an ANALYZE/NIfTI .hdr/.img pair) through niftiio.
// A 3D image gives one ScalarImage, a 4D image one per time frame (dim[4]). Trailing dimensions
// of size 1 beyond the 4th are accepted; axes beyond dim[0] count as size 1.
// Datatypes: uint8, int8, uint16, int16, uint32, int32, float32, float64.
// Spacing is pixdim[1..3] converted to mm from xyzt_units (metre, micron; unknown = mm).
// Throws bop::Error(path, ...) for a missing/unreadable file, a file that is not NIfTI-1,
// unreadable image data, an unsupported datatype, more than 4 dimensions, a zero dimension
// or non-positive spacing.
// keep: when given, every frame is cut to the box of the voxels whose value it accepts in any
// frame, originMm set to the box's corner (only the box is converted to float: a 56k-voxel organ
// of a 32 M-voxel scan costs the file's samples and the box); an image where it accepts none is
// returned whole.
std::vector<ScalarImage> loadNifti(const std::string& path, const KeepFn& keep = {});

// Layout of a headerless raw file: optional header bytes, then `frames` volumes stored one
// after another, each x fastest.
struct RawLayout {
    Dims dims;          // voxels per axis
    std::string dtype;  // "uint8","int8","uint16","int16","uint32","int32","float32","float64"
    Eigen::Vector3d spacingMm = Eigen::Vector3d::Ones();  // voxel spacing per axis, mm
    bool bigEndian = false;                               // byte order of multi-byte samples (true = big-endian)
    std::size_t headerBytes = 0;                          // bytes skipped at the start, bytes
    int frames = 1;                                       // time frames stored one after another, count
};

// Reads a raw file; its size must be exactly headerBytes + frames * dims.count() * sizeof(dtype).
// Throws bop::Error(path, ...) for a missing file, a size mismatch (naming both byte counts),
// an unknown dtype (naming the accepted ones), non-positive dims, frames or spacing.
// keep: as for loadNifti.
std::vector<ScalarImage> loadRaw(const std::string& path, const RawLayout& layout, const KeepFn& keep = {});

// Writes one 3D image as NIfTI-1; .nii or .nii.gz chosen by the extension of path.
// pixdim[1..3] = spacingMm, units mm, no qform/sform. Integer dtypes round each value to the
// nearest integer; a value outside the dtype's range (or NaN) throws bop::Error(path, ...).
void writeNifti(const std::string& path, const ScalarImage& img, const std::string& dtype = "uint8");

// Writes frames as one 4D NIfTI-1 image (dim[4] = frames.size(), even for one frame); all frames
// must share dims and spacing.
void writeNifti4d(const std::string& path, const std::vector<ScalarImage>& frames, const std::string& dtype = "uint8");

}  // namespace bop::shape
