#pragma once
// The messages bop-igtl sends, in OpenIGTLink protocol version 2: POLYDATA for particles (points,
// one vertex cell each, normals and species as point data) and for the probe's reaction force (a
// line), packed here from the specification's layout (fast enough for 10^4 particles at 60 Hz);
// TRANSFORM for the probe and IMAGE for the scene's label map, packed by the reference library
// (Debian's libopenigtlink). Lengths in mm, in the receiver's RAS frame.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bop::igtl {

using Bytes = std::vector<std::uint8_t>;

struct PointSet {
    std::vector<Eigen::Vector3f> points;   // mm
    std::vector<Eigen::Vector3f> normals;  // unit, one per point, or empty
    std::vector<float> species;            // BoP's species number per point, or empty
};

// POLYDATA: the points, each its own vertex cell, with "Normals" and "Species" point data.
Bytes polyData(const std::string& device, const PointSet& set);
// POLYDATA: one line from `from` to `to` (mm).
Bytes line(const std::string& device, const Eigen::Vector3f& from, const Eigen::Vector3f& to);
// TRANSFORM: a 4 x 4 matrix (mm).
Bytes transform(const std::string& device, const Eigen::Matrix4d& m);

struct LabelImage {
    std::array<int, 3> dims{};                               // voxels, i fastest
    Eigen::Matrix4d ijkToRas = Eigen::Matrix4d::Identity();  // voxel index to that voxel's centre, mm
    std::vector<std::uint8_t> labels;                        // dims[0] dims[1] dims[2] values, 0 outside
};
// IMAGE: an 8-bit label volume. The message places an image by the centre of its voxel grid, its
// axes' unit directions and its spacing (the specification's IMAGE; 3D Slicer's converter takes
// the centre back to the first voxel's): all three from ijkToRas.
Bytes labelImage(const std::string& device, const LabelImage& image);

}  // namespace bop::igtl
