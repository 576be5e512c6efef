#include "FileSources.hpp"

#include "MeshVoxelizer.hpp"
#include "TriangleMesh.hpp"

#include <algorithm>

namespace bop::shape {
namespace {

class MeshSource final : public ModelSource {
public:
    MeshSource(TriangleMesh mesh, std::string path) : mesh_(std::move(mesh)), path_(std::move(path)) {}
    Eigen::AlignedBox3d boundsMm(int) const override { return meshBounds(mesh_); }
    void rasterize(int, const VoxelGrid& g, Mask& out) const override { voxelizeMesh(mesh_, g, out); }
    std::string describe() const override {
        return "mesh " + path_ + " (" + std::to_string(mesh_.triangles.size()) + " triangles)";
    }

private:
    TriangleMesh mesh_;
    std::string path_;
};

class ImageSource final : public ModelSource {
public:
    ImageSource(std::vector<ScalarImage> frames, const ImageSelect& sel, std::string what)
        : frames_(std::move(frames)), sel_(sel), what_(std::move(what)) {}
    int frameCount() const override { return int(frames_.size()); }
    Eigen::AlignedBox3d boundsMm(int f) const override { return imageBounds(frames_[std::size_t(f)]); }
    void rasterize(int f, const VoxelGrid& g, Mask& out) const override {
        rasterizeImage(frames_[std::size_t(f)], sel_, g, out);
    }
    double naturalVoxelMm() const override { return frames_.front().spacingMm.minCoeff(); }
    std::string describe() const override { return what_; }

private:
    std::vector<ScalarImage> frames_;
    ImageSelect sel_;
    std::string what_;
};

}  // namespace

std::unique_ptr<ModelSource> makeMeshSource(const std::string& path, double scaleMm, const Eigen::Vector3d& offsetMm) {
    TriangleMesh mesh = loadMesh(path);
    requireClosed(mesh, path);
    for (auto& v : mesh.vertices) v = v * scaleMm + offsetMm;
    return std::make_unique<MeshSource>(std::move(mesh), path);
}

std::unique_ptr<ModelSource> makeImageSource(std::vector<ScalarImage> frames, const ImageSelect& sel,
                                             const std::string& description) {
    return std::make_unique<ImageSource>(std::move(frames), sel, description);
}

}  // namespace bop::shape
