#include "MeshVoxelizer.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace bop::shape {
namespace {

// Fixed offsets of every ray within its projected plane, in voxels: tiny irrational fractions, so
// that rays through grid-aligned mesh features (edges, vertices on voxel-centre lines) miss them.
constexpr double kOffsetU = 0.41421356237309505e-6;  // (sqrt(2) - 1) * 1e-6 voxel
constexpr double kOffsetV = 0.73205080756887729e-6;  // (sqrt(3) - 1) * 1e-6 voxel
constexpr double kRowMargin = 1e-7;                  // slack when choosing the rows a triangle's bounds cover, voxels

// One ray direction: rays run along axis a (+a); rows are indexed by the other two axes u < v.
struct RayAxis {
    int a, u, v;  // axis numbers, 0 = x, 1 = y, 2 = z
};

struct Crossing {
    std::size_t row;  // row index iu + nu * iv
    double at;        // coordinate of the crossing along the ray axis, mm
    int sign;         // +1 where the ray leaves the solid (outward normal along the ray), -1 where it enters
};

// Twice the signed area of (from, to, p) in the projected (u, v) plane, mm^2. Evaluated from the
// lower vertex index so that the two triangles sharing an edge get exactly opposite values.
double edgeValue(const TriangleMesh& mesh, int from, int to, int u, int v, double pu, double pv) {
    if (from > to) return -edgeValue(mesh, to, from, u, v, pu, pv);
    const Eigen::Vector3d& p0 = mesh.vertices[std::size_t(from)];
    const Eigen::Vector3d& p1 = mesh.vertices[std::size_t(to)];
    return (p1[u] - p0[u]) * (pv - p0[v]) - (p1[v] - p0[v]) * (pu - p0[u]);
}

// Sign of an edge value, never zero: a point exactly on the edge's line counts as moved by
// (e, e^2) in (u, v) for an infinitesimal e > 0 (simulation of simplicity), which gives the two
// triangles sharing the edge opposite signs, so exactly one of them is hit.
int edgeSign(double value, const TriangleMesh& mesh, int from, int to, int u, int v) {
    if (value != 0.0) return value > 0.0 ? 1 : -1;
    const double du = mesh.vertices[std::size_t(to)][u] - mesh.vertices[std::size_t(from)][u];  // mm
    const double dv = mesh.vertices[std::size_t(to)][v] - mesh.vertices[std::size_t(from)][v];  // mm
    if (dv != 0.0) return dv < 0.0 ? 1 : -1;  // value(p + (e, e^2)) = du e^2 - dv e
    return du > 0.0 ? 1 : -1;
}

// Rows [lo, hi] (clamped to [0, n - 1]) whose ray coordinate origin + h (i + 0.5 + offset) lies
// within [low, high] mm; lo > hi when none.
void rowRange(double low, double high, double origin, double h, double offset, int n, int& lo, int& hi) {
    const double first = std::ceil((low - origin) / h - 0.5 - offset - kRowMargin);
    const double last = std::floor((high - origin) / h - 0.5 - offset + kRowMargin);
    lo = int(std::clamp(first, 0.0, double(n)));
    hi = int(std::clamp(last, -1.0, double(n - 1)));
}

// Appends the crossings of every row's ray along axis.a with the mesh triangles.
void collectCrossings(const TriangleMesh& mesh, const VoxelGrid& grid, const std::array<int, 3>& n, RayAxis axis,
                      std::vector<Crossing>& crossings) {
    const auto [a, u, v] = axis;
    const double h = grid.voxelMm;                              // mm
    const double ou = grid.originMm[u], ov = grid.originMm[v];  // mm
    for (const auto& tri : mesh.triangles) {
        const Eigen::Vector3d& p0 = mesh.vertices[std::size_t(tri[0])];
        const Eigen::Vector3d& p1 = mesh.vertices[std::size_t(tri[1])];
        const Eigen::Vector3d& p2 = mesh.vertices[std::size_t(tri[2])];
        int uLo, uHi, vLo, vHi;
        rowRange(std::min({p0[u], p1[u], p2[u]}), std::max({p0[u], p1[u], p2[u]}), ou, h, kOffsetU, n[u], uLo, uHi);
        rowRange(std::min({p0[v], p1[v], p2[v]}), std::max({p0[v], p1[v], p2[v]}), ov, h, kOffsetV, n[v], vLo, vHi);
        for (int iv = vLo; iv <= vHi; ++iv) {
            const double pv = ov + h * (double(iv) + (0.5 + kOffsetV));  // ray v coordinate, mm
            for (int iu = uLo; iu <= uHi; ++iu) {
                const double pu = ou + h * (double(iu) + (0.5 + kOffsetU));       // ray u coordinate, mm
                const double w0 = edgeValue(mesh, tri[1], tri[2], u, v, pu, pv);  // weight of p0
                const double w1 = edgeValue(mesh, tri[2], tri[0], u, v, pu, pv);  // weight of p1
                const double w2 = edgeValue(mesh, tri[0], tri[1], u, v, pu, pv);  // weight of p2
                const int s0 = edgeSign(w0, mesh, tri[1], tri[2], u, v);
                if (edgeSign(w1, mesh, tri[2], tri[0], u, v) != s0 || edgeSign(w2, mesh, tri[0], tri[1], u, v) != s0)
                    continue;
                const double sum = w0 + w1 + w2;
                if (sum == 0.0) continue;                            // degenerate in projection
                const double normalA = (p1 - p0).cross(p2 - p0)[a];  // the normal's component along the ray
                crossings.push_back({std::size_t(iu) + std::size_t(n[u]) * std::size_t(iv),
                                     (w0 * p0[a] + w1 * p1[a] + w2 * p2[a]) / sum, normalA > 0 ? 1 : -1});
            }
        }
    }
}

// First index i in [0, n] whose centre origin + h (i + 0.5) is >= at (n if none).
int firstCentreAtOrAbove(double at, double origin, double h, int n) {
    const double guess = std::ceil((at - origin) / h - 0.5);
    if (!(guess > 0.0)) return 0;
    if (guess >= double(n)) return n;
    int i = int(guess);
    while (i > 0 && origin + h * (double(i - 1) + 0.5) >= at) --i;  // same formula as VoxelGrid::centreMm
    while (i < n && origin + h * (double(i) + 0.5) < at) ++i;
    return i;
}

}  // namespace

void voxelizeMesh(const TriangleMesh& mesh, const VoxelGrid& grid, Mask& out) {
    const Dims& d = grid.dims;
    if (d.nx < 0 || d.ny < 0 || d.nz < 0) throw Error("voxelizeMesh", "grid dimensions must not be negative");
    if (!std::isfinite(grid.voxelMm) || grid.voxelMm <= 0.0 || !grid.originMm.allFinite())
        throw Error("voxelizeMesh", "voxel size must be finite and > 0 mm, origin finite; got voxel size " +
                                        std::to_string(grid.voxelMm) + " mm");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (const int index : mesh.triangles[t])
            if (index < 0 || std::size_t(index) >= mesh.vertices.size())
                throw Error("voxelizeMesh", "triangle " + std::to_string(t) + " refers to vertex " +
                                                std::to_string(index) + ", but the mesh has " +
                                                std::to_string(mesh.vertices.size()) + " vertices");
    for (const Eigen::Vector3d& p : mesh.vertices)
        if (!p.allFinite()) throw Error("voxelizeMesh", "mesh has a vertex with a non-finite coordinate");
    out = Mask(d, 0);
    if (d.count() == 0) return;

    // out.data counts the rays (0..3) that find the centre inside; thresholded at the end.
    const std::array<int, 3> n{d.nx, d.ny, d.nz};  // voxels per axis
    const std::array<std::size_t, 3> stride{1, std::size_t(d.nx), std::size_t(d.nx) * std::size_t(d.ny)};
    std::vector<Crossing> crossings;
    std::vector<std::size_t> rowStart, cursor;   // per row: first crossing in `sorted`, next free slot
    std::vector<std::pair<double, int>> sorted;  // (coordinate mm, sign) of the crossings grouped by row
    for (const RayAxis axis : {RayAxis{0, 1, 2}, RayAxis{1, 0, 2}, RayAxis{2, 0, 1}}) {
        crossings.clear();
        collectCrossings(mesh, grid, n, axis, crossings);

        // Counting sort of the crossings by row, then sort each row's few crossings along the ray.
        const std::size_t nu = std::size_t(n[axis.u]), rows = nu * std::size_t(n[axis.v]);
        rowStart.assign(rows + 1, 0);
        for (const Crossing& c : crossings) ++rowStart[c.row + 1];
        std::partial_sum(rowStart.begin(), rowStart.end(), rowStart.begin());
        cursor.assign(rowStart.begin(), rowStart.end() - 1);
        sorted.resize(crossings.size());
        for (const Crossing& c : crossings) sorted[cursor[c.row]++] = {c.at, c.sign};

        const double origin = grid.originMm[axis.a];  // mm
        const std::size_t step = stride[std::size_t(axis.a)];
        for (std::size_t row = 0; row < rows; ++row) {
            const auto begin = sorted.begin() + std::ptrdiff_t(rowStart[row]);
            const auto end = sorted.begin() + std::ptrdiff_t(rowStart[row + 1]);
            if (end - begin < 2) continue;
            std::sort(begin, end);
            std::uint8_t* base =
                out.data.data() + (row % nu) * stride[std::size_t(axis.u)] + (row / nu) * stride[std::size_t(axis.v)];
            // The winding number of a centre is the sum of the signs of the crossings ahead of it
            // (at > centre); inside where it is 1 or more (self-overlapping parts count once).
            int winding = 0, above = n[axis.a];
            for (auto c = end; c != begin;) {
                --c;
                const int from = firstCentreAtOrAbove(c->first, origin, grid.voxelMm, n[axis.a]);
                if (winding >= 1)
                    for (int i = from; i < above; ++i) ++base[std::size_t(i) * step];
                winding += c->second;
                above = from;
            }
            if (winding >= 1)
                for (int i = 0; i < above; ++i) ++base[std::size_t(i) * step];
        }
    }
    for (std::uint8_t& votes : out.data) votes = votes >= 2 ? 1 : 0;
}

}  // namespace bop::shape
