#pragma once
// Voxel grids and dense per-voxel arrays. Index order is x fastest:
// index(i, j, k) = i + nx * (j + ny * k), so a NumPy view has shape (nz, ny, nx).
#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace bop {

struct Dims {
    int nx = 0, ny = 0, nz = 0;  // voxels per axis

    std::size_t count() const { return std::size_t(nx) * std::size_t(ny) * std::size_t(nz); }
    std::size_t index(int i, int j, int k) const {
        return std::size_t(i) + std::size_t(nx) * (std::size_t(j) + std::size_t(ny) * std::size_t(k));
    }
    Eigen::Vector3i coords(std::size_t idx) const {
        const int i = int(idx % std::size_t(nx));
        const std::size_t r = idx / std::size_t(nx);
        return {i, int(r % std::size_t(ny)), int(r / std::size_t(ny))};
    }
    bool contains(int i, int j, int k) const { return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz; }
    bool operator==(const Dims&) const = default;
};

// Placement of a cubic-voxel grid in model space (millimetres).
struct VoxelGrid {
    Dims dims;
    Eigen::Vector3d originMm = Eigen::Vector3d::Zero();  // corner of voxel (0,0,0), mm
    double voxelMm = 1.0;                                // voxel edge length, mm

    // Centre of voxel (i, j, k) in model space, mm.
    Eigen::Vector3d centreMm(int i, int j, int k) const {
        return originMm + voxelMm * Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5);
    }
};

template <class T>
struct Volume {
    Dims dims;
    std::vector<T> data;

    Volume() = default;
    explicit Volume(Dims d, T fill = T{}) : dims(d), data(d.count(), fill) {}
    T& operator()(int i, int j, int k) { return data[dims.index(i, j, k)]; }
    const T& operator()(int i, int j, int k) const { return data[dims.index(i, j, k)]; }
};

using Mask = Volume<std::uint8_t>;  // 1 = object voxel, 0 = non-object

}  // namespace bop
