#pragma once
// A model source turns one bag's description into object voxels on a grid: analytic shapes
// (superellipsoid, torus), triangle meshes (OBJ, STL, PLY, glTF, ...) and segmented images (NIfTI, raw).
// A source may hold several time frames (image sequences); analytic and mesh sources hold one.
#include "bop/common/Volume.hpp"

#include <Eigen/Geometry>

#include <memory>
#include <string>

namespace bop::shape {

class ModelSource {
public:
    virtual ~ModelSource() = default;
    virtual int frameCount() const { return 1; }
    // Bounding box of the object in model space, mm.
    virtual Eigen::AlignedBox3d boundsMm(int frame) const = 0;
    // Sets out(v) = 1 where the centre of v lies in the object, 0 elsewhere; out has grid.dims.
    virtual void rasterize(int frame, const VoxelGrid& grid, Mask& out) const = 0;
    // Isotropic voxel size the data suggests, mm (images: their finest spacing); 0 = none.
    virtual double naturalVoxelMm() const { return 0.0; }
    // The data's coarsest sample spacing, mm (images: their largest spacing, the slices'); 0 = none.
    virtual double coarsestSpacingMm() const { return 0.0; }
    virtual std::string describe() const = 0;
    // What the source found and mended in its input, for a warning; "" when nothing.
    const std::string& warning() const { return warning_; }
    void setWarning(std::string w) { warning_ = std::move(w); }

private:
    std::string warning_;
};

// Superellipsoid (Barr): ((|x/a|^(2/e2) + |y/b|^(2/e2))^(e2/e1) + |z/c|^(2/e1)) <= 1.
// e1 (north-south) and e2 (east-west) exponents: 1 gives an ellipsoid, > 2 a star-like
// concave shape, < 1 a rounded box.
struct SuperellipsoidParams {
    Eigen::Vector3d radiiMm{10, 10, 10};  // semi-axes a, b, c, mm
    double e1 = 1.0, e2 = 1.0;            // exponents, dimensionless
    Eigen::Vector3d centreMm = Eigen::Vector3d::Zero();
};

// Torus around the z axis: (sqrt(x^2 + y^2) - R)^2 + z^2 <= r^2.
struct TorusParams {
    double majorMm = 30.0;  // R, distance from the axis to the tube centre, mm
    double minorMm = 12.0;  // r, tube radius, mm
    Eigen::Vector3d centreMm = Eigen::Vector3d::Zero();
};

std::unique_ptr<ModelSource> makeSuperellipsoid(const SuperellipsoidParams& p);
std::unique_ptr<ModelSource> makeTorus(const TorusParams& p);

// Volume of a superellipsoid, mm^3 (Jaklic et al.): 2abc e1 e2 B(e1/2 + 1, e1) B(e2/2, e2/2).
double superellipsoidVolume(const SuperellipsoidParams& p);

}  // namespace bop::shape
