#include "MeshRepair.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <sstream>

namespace bop::shape {
namespace {

struct EdgeUse {
    std::uint64_t key;  // undirected edge: lower vertex << 32 | higher vertex
    std::uint32_t triangle;
    bool forward;  // used from the lower to the higher vertex
};

std::vector<EdgeUse> edgeUses(const TriangleMesh& mesh) {
    std::vector<EdgeUse> uses;
    uses.reserve(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int e = 0; e < 3; ++e) {
            const auto a = std::uint64_t(mesh.triangles[t][std::size_t(e)]);
            const auto b = std::uint64_t(mesh.triangles[t][std::size_t((e + 1) % 3)]);
            uses.push_back({a < b ? (a << 32 | b) : (b << 32 | a), std::uint32_t(t), a < b});
        }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
    });
    return uses;
}

// Calls f(first, last) for each run of uses of one undirected edge.
template <class F>
void forEachEdge(const std::vector<EdgeUse>& uses, F f) {
    for (std::size_t first = 0; first < uses.size();) {
        std::size_t last = first;
        while (last < uses.size() && uses[last].key == uses[first].key) ++last;
        f(first, last);
        first = last;
    }
}

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

void flip(std::array<int, 3>& tri) {
    std::swap(tri[1], tri[2]);
}

}  // namespace

std::string MeshRepair::summary() const {
    std::ostringstream os;
    if (boundaryEdges || nonManifoldEdges)
        os << boundaryEdges << " boundary edges and " << nonManifoldEdges
           << " non-manifold edges: the generalized winding number decides inside; ";
    if (components > 1) os << components << " separate pieces; ";
    if (flipped) os << flipped << " triangles turned to agree with their neighbours; ";
    if (turnedOut) os << "the mesh was inside out and was turned; ";
    if (degenerate) os << degenerate << " zero-area triangles dropped; ";
    std::string s = os.str();
    if (s.size() >= 2) s.resize(s.size() - 2);
    return s;
}

MeshRepair repairMesh(TriangleMesh& mesh) {
    MeshRepair r;
    std::erase_if(mesh.triangles, [&](const std::array<int, 3>& t) {
        const Eigen::Vector3d& a = mesh.vertices[std::size_t(t[0])];
        const bool zero =
            t[0] == t[1] || t[1] == t[2] || t[0] == t[2] ||
            (mesh.vertices[std::size_t(t[1])] - a).cross(mesh.vertices[std::size_t(t[2])] - a).squaredNorm() == 0.0;
        r.degenerate += zero;
        return zero;
    });
    const std::size_t n = mesh.triangles.size();
    r.triangles = n;

    // Neighbours across manifold edges (whether they agree), pieces through any shared edge.
    std::vector<EdgeUse> uses = edgeUses(mesh);
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<std::vector<std::pair<std::uint32_t, bool>>> next(n);  // (neighbour, same direction)
    forEachEdge(uses, [&](std::size_t first, std::size_t last) {
        const std::size_t count = last - first;
        r.boundaryEdges += count == 1;
        r.nonManifoldEdges += count > 2;
        for (std::size_t u = first + 1; u < last; ++u)
            parent[findRoot(parent, uses[u].triangle)] = findRoot(parent, uses[first].triangle);
        if (count != 2) return;
        const EdgeUse& a = uses[first];
        const EdgeUse& b = uses[first + 1];
        next[a.triangle].push_back({b.triangle, a.forward == b.forward});
        next[b.triangle].push_back({a.triangle, a.forward == b.forward});
    });
    for (std::uint32_t t = 0; t < n; ++t) r.components += findRoot(parent, t) == t;

    // Breadth-first over manifold edges: each triangle takes the orientation that agrees with the
    // one it was reached from; in each patch the smaller side is the one turned.
    std::vector<int> turn(n, -1);
    std::vector<std::uint32_t> patch;
    for (std::uint32_t start = 0; start < n; ++start) {
        if (turn[start] >= 0) continue;
        patch.assign(1, start);
        turn[start] = 0;
        std::size_t turned = 0;
        for (std::size_t head = 0; head < patch.size(); ++head) {
            const std::uint32_t t = patch[head];
            for (const auto& [u, same] : next[t]) {
                if (turn[u] >= 0) continue;  // a disagreement left (a non-orientable patch) is ignored
                turn[u] = turn[t] ^ int(same);
                turned += std::size_t(turn[u]);
                patch.push_back(u);
            }
        }
        const bool invert = 2 * turned > patch.size();
        for (const std::uint32_t t : patch)
            if ((turn[t] != 0) != invert) {
                flip(mesh.triangles[t]);
                ++r.flipped;
            }
    }

    // Signed volume about the centroid (open meshes: the cone from it over the surface).
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& v : mesh.vertices) centre += v;
    centre /= double(std::max<std::size_t>(1, mesh.vertices.size()));
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d a = mesh.vertices[std::size_t(t[0])] - centre;
        const Eigen::Vector3d b = mesh.vertices[std::size_t(t[1])] - centre;
        const Eigen::Vector3d c = mesh.vertices[std::size_t(t[2])] - centre;
        r.volume += a.dot(b.cross(c)) / 6.0;
        r.area += 0.5 * (b - a).cross(c - a).norm();
    }
    if (r.volume < 0) {
        for (auto& t : mesh.triangles) flip(t);
        r.volume = -r.volume;
        r.turnedOut = true;
    }

    uses = edgeUses(mesh);
    r.closed = n > 0;
    forEachEdge(uses, [&](std::size_t first, std::size_t last) {
        std::ptrdiff_t balance = 0;
        for (std::size_t u = first; u < last; ++u) balance += uses[u].forward ? 1 : -1;
        if (balance != 0) r.closed = false;
    });
    return r;
}

}  // namespace bop::shape
