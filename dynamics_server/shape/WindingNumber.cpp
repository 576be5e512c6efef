#include "WindingNumber.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace bop::shape {
namespace {

// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom and Strackee),
// positive when the triangle turns counter-clockwise seen from the far side; steradians.
double solidAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    return 2.0 * std::atan2(num, den);
}

}  // namespace

WindingNumber::WindingNumber(const TriangleMesh& mesh) {
    tris_.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles)
        tris_.push_back(
            {mesh.vertices[std::size_t(t[0])], mesh.vertices[std::size_t(t[1])], mesh.vertices[std::size_t(t[2])]});
    nodes_.reserve(2 * tris_.size() / kLeafSize + 2);
    if (!tris_.empty()) build(0, int(tris_.size()));
}

int WindingNumber::build(int first, int count) {
    const int index = int(nodes_.size());
    nodes_.emplace_back();
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), dipole = Eigen::Vector3d::Zero();
    Eigen::AlignedBox3d centroids;
    double area = 0;
    for (int t = first; t < first + count; ++t) {
        const auto& [a, b, c] = tris_[std::size_t(t)];
        const Eigen::Vector3d n = 0.5 * (b - a).cross(c - a);
        const double at = n.norm();
        weighted += at * (a + b + c) / 3.0;
        dipole += n;
        area += at;
        centroids.extend((a + b + c) / 3.0);
    }
    Eigen::Vector3d centre = area > 0 ? Eigen::Vector3d(weighted / area) : centroids.center();
    double far2 = 0;
    for (int t = first; t < first + count; ++t)
        for (const auto& p : tris_[std::size_t(t)]) far2 = std::max(far2, (p - centre).squaredNorm());
    Node node{centre, dipole, kFarFactor * kFarFactor * far2, first, count};
    if (count > kLeafSize) {
        int axis;
        centroids.sizes().maxCoeff(&axis);
        const auto begin = tris_.begin() + first, end = begin + count, mid = begin + count / 2;
        std::nth_element(begin, mid, end, [axis](const auto& x, const auto& y) {
            return x[0][axis] + x[1][axis] + x[2][axis] < y[0][axis] + y[1][axis] + y[2][axis];
        });
        node.left = build(first, count / 2);
        node.right = build(first + count / 2, count - count / 2);
    }
    nodes_[std::size_t(index)] = node;
    return index;
}

double WindingNumber::at(const Eigen::Vector3d& q) const {
    if (nodes_.empty()) return 0.0;
    double sum = 0;  // steradians
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& node = nodes_[std::size_t(stack[--top])];
        const Eigen::Vector3d d = node.centre - q;
        const double d2 = d.squaredNorm();
        if (d2 > node.radius2) {
            sum += d.dot(node.dipole) / (d2 * std::sqrt(d2));  // the node's normals as one dipole
        } else if (node.left < 0) {
            for (int t = node.first; t < node.first + node.count; ++t) {
                const auto& [a, b, c] = tris_[std::size_t(t)];
                sum += solidAngle(a - q, b - q, c - q);
            }
        } else {
            stack[top++] = node.left;
            stack[top++] = node.right;
        }
    }
    return sum / (4.0 * std::numbers::pi);
}

double WindingNumber::exactAt(const Eigen::Vector3d& q) const {
    double sum = 0;
    for (const auto& [a, b, c] : tris_) sum += solidAngle(a - q, b - q, c - q);
    return sum / (4.0 * std::numbers::pi);
}

void voxelizeByWindingNumber(const WindingNumber& w, const VoxelGrid& grid, Mask& out, int threads) {
    const Dims d = grid.dims;
    out = Mask(d, 0);
#ifdef _OPENMP
    const int team = threads > 0 ? threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
#else
    (void)threads;
#endif
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) out(i, j, k) = w.at(grid.centreMm(i, j, k)) >= 0.5 ? 1 : 0;
}

}  // namespace bop::shape
