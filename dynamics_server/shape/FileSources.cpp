#include "FileSources.hpp"

#include "MeshRepair.hpp"
#include "MeshVoxelizer.hpp"
#include "TriangleMesh.hpp"
#include "WindingNumber.hpp"
#include "bop/common/Error.hpp"

#include <algorithm>
#include <optional>
#include <sstream>

namespace bop::shape {
namespace {

class MeshSource final : public ModelSource {
public:
    MeshSource(TriangleMesh mesh, const MeshRepair& repair, std::string path)
        : mesh_(std::move(mesh)), path_(std::move(path)) {
        if (!repair.closed) winding_.emplace(mesh_);
        if (const std::string s = repair.summary(); !s.empty()) setWarning("mesh " + path_ + ": " + s);
    }
    Eigen::AlignedBox3d boundsMm(int) const override { return meshBounds(mesh_); }
    void rasterize(int, const VoxelGrid& g, Mask& out) const override {
        if (winding_)
            voxelizeByWindingNumber(*winding_, g, out);
        else
            voxelizeMesh(mesh_, g, out);
    }
    std::string describe() const override {
        return "mesh " + path_ + " (" + std::to_string(mesh_.triangles.size()) + " triangles)";
    }

private:
    TriangleMesh mesh_;
    std::string path_;
    std::optional<WindingNumber> winding_;  // meshes that are not closed
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
    double coarsestSpacingMm() const override { return frames_.front().spacingMm.maxCoeff(); }
    std::string describe() const override { return what_; }

private:
    std::vector<ScalarImage> frames_;
    ImageSelect sel_;
    std::string what_;
};

}  // namespace

std::unique_ptr<ModelSource> makeMeshSource(const std::string& path, const MeshPlacement& placement) {
    TriangleMesh mesh = loadMesh(path);
    const MeshRepair repair = repairMesh(mesh);
    const Eigen::Vector3d sides = meshBounds(mesh).sizes();  // file units
    if (repair.triangles == 0 || !(sides.minCoeff() > 1e-6 * sides.maxCoeff())) {
        std::ostringstream os;
        os << "mesh is flat: its bounds measure " << sides.x() << " x " << sides.y() << " x " << sides.z()
           << " file units" << (repair.triangles == 0 ? " and every triangle has zero area" : "")
           << "; a surface around a solid is expected";
        throw Error(path, os.str());
    }
    if (repair.closed && !(repair.volume > 1e-9 * sides.prod())) {
        std::ostringstream os;
        os << "mesh encloses no volume (" << repair.volume << " cubic file units inside bounds of " << sides.x()
           << " x " << sides.y() << " x " << sides.z() << "); a surface around a solid is expected";
        throw Error(path, os.str());
    }
    const double scale = placement.fitVoxels > 0 ? placement.fitVoxels * placement.voxelMm / sides.maxCoeff()
                                                 : placement.scaleMm;  // mm per file unit
    for (auto& v : mesh.vertices) v = v * scale + placement.offsetMm;
    return std::make_unique<MeshSource>(std::move(mesh), repair, path);
}

std::unique_ptr<ModelSource> makeImageSource(std::vector<ScalarImage> frames, const ImageSelect& sel,
                                             const std::string& description) {
    return std::make_unique<ImageSource>(std::move(frames), sel, description);
}

}  // namespace bop::shape
