#include "ModelSource.hpp"

#include <cmath>
#include <sstream>

namespace bop::shape {
namespace {

// Voxel index range [lo, hi) whose centres may fall inside a box, clamped to the grid.
void voxelRange(const VoxelGrid& g, const Eigen::AlignedBox3d& box, Eigen::Vector3i& lo, Eigen::Vector3i& hi) {
    const Eigen::Vector3i n(g.dims.nx, g.dims.ny, g.dims.nz);
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(0, int(std::floor((box.min()[a] - g.originMm[a]) / g.voxelMm - 0.5)));
        hi[a] = std::min(n[a], int(std::ceil((box.max()[a] - g.originMm[a]) / g.voxelMm + 0.5)) + 1);
    }
}

template <class Inside>
void fill(const VoxelGrid& g, const Eigen::AlignedBox3d& box, Mask& out, Inside inside) {
    out = Mask(g.dims, 0);
    Eigen::Vector3i lo, hi;
    voxelRange(g, box, lo, hi);
#pragma omp parallel for schedule(static)
    for (int k = lo.z(); k < hi.z(); ++k)
        for (int j = lo.y(); j < hi.y(); ++j)
            for (int i = lo.x(); i < hi.x(); ++i) out(i, j, k) = inside(g.centreMm(i, j, k)) ? 1 : 0;
}

class Superellipsoid final : public ModelSource {
public:
    explicit Superellipsoid(const SuperellipsoidParams& p) : p_(p) {}
    Eigen::AlignedBox3d boundsMm(int) const override { return {p_.centreMm - p_.radiiMm, p_.centreMm + p_.radiiMm}; }
    void rasterize(int, const VoxelGrid& g, Mask& out) const override {
        const double ex = 2.0 / p_.e2, ez = 2.0 / p_.e1, exy = p_.e2 / p_.e1;
        fill(g, boundsMm(0), out, [&](const Eigen::Vector3d& x) {
            const Eigen::Vector3d u = (x - p_.centreMm).cwiseQuotient(p_.radiiMm).cwiseAbs();
            const double xy = std::pow(u.x(), ex) + std::pow(u.y(), ex);
            return std::pow(xy, exy) + std::pow(u.z(), ez) <= 1.0;
        });
    }
    std::string describe() const override {
        std::ostringstream os;
        os << "superellipsoid radii " << p_.radiiMm.transpose() << " mm, exponents " << p_.e1 << ", " << p_.e2;
        return os.str();
    }

private:
    SuperellipsoidParams p_;
};

class Torus final : public ModelSource {
public:
    explicit Torus(const TorusParams& p) : p_(p) {}
    Eigen::AlignedBox3d boundsMm(int) const override {
        const Eigen::Vector3d e(p_.majorMm + p_.minorMm, p_.majorMm + p_.minorMm, p_.minorMm);
        return {p_.centreMm - e, p_.centreMm + e};
    }
    void rasterize(int, const VoxelGrid& g, Mask& out) const override {
        fill(g, boundsMm(0), out, [&](const Eigen::Vector3d& x) {
            const Eigen::Vector3d u = x - p_.centreMm;
            const double rho = std::hypot(u.x(), u.y()) - p_.majorMm;
            return rho * rho + u.z() * u.z() <= p_.minorMm * p_.minorMm;
        });
    }
    std::string describe() const override {
        std::ostringstream os;
        os << "analytic torus R = " << p_.majorMm << " mm, r = " << p_.minorMm << " mm";
        return os.str();
    }

private:
    TorusParams p_;
};

}  // namespace

std::unique_ptr<ModelSource> makeSuperellipsoid(const SuperellipsoidParams& p) {
    return std::make_unique<Superellipsoid>(p);
}
std::unique_ptr<ModelSource> makeTorus(const TorusParams& p) {
    return std::make_unique<Torus>(p);
}

double superellipsoidVolume(const SuperellipsoidParams& p) {
    return 2.0 * p.radiiMm.prod() * p.e1 * p.e2 * std::beta(p.e1 / 2 + 1, p.e1) * std::beta(p.e2 / 2, p.e2 / 2);
}

}  // namespace bop::shape
