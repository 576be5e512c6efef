#include "MeshTestUtil.hpp"

#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>

namespace bop::test {
using shape::TriangleMesh;

std::string torusPath() {
    return sourceDir() + "/config/models/torus.obj";
}

double signedVolume(const TriangleMesh& mesh) {
    double sixTimes = 0.0;
    for (const auto& t : mesh.triangles)
        sixTimes += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
    return sixTimes / 6.0;
}

VoxelGrid gridAround(const TriangleMesh& mesh, double voxelMm, int padVoxels) {
    const Eigen::AlignedBox3d box = meshBounds(mesh);
    VoxelGrid grid;
    grid.voxelMm = voxelMm;
    grid.originMm = box.min() - Eigen::Vector3d::Constant(padVoxels * voxelMm);
    const Eigen::Vector3d extent = box.sizes() / voxelMm;
    grid.dims = {int(std::ceil(extent.x())) + 2 * padVoxels, int(std::ceil(extent.y())) + 2 * padVoxels,
                 int(std::ceil(extent.z())) + 2 * padVoxels};
    return grid;
}

std::size_t countSet(const Mask& mask) {
    std::size_t n = 0;
    for (const auto v : mask.data) n += v != 0;
    return n;
}

void writeObj(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(17);
    for (const auto& p : mesh.vertices) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

namespace {
Eigen::Vector3d unitNormal(const TriangleMesh& mesh, const std::array<int, 3>& t) {
    const auto& a = mesh.vertices[t[0]];
    return (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).normalized();
}

}  // namespace

void writeAsciiStl(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(17);
    out << "solid test mesh\n";
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d n = unitNormal(mesh, t);
        out << "  facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\n    outer loop\n";
        for (const int i : t) {
            const auto& p = mesh.vertices[i];
            out << "      vertex " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
        }
        out << "    endloop\n  endfacet\n";
    }
    out << "endsolid test mesh\n";
}

namespace {
void putLittle32(std::ofstream& out, std::uint32_t value) {
    for (int b = 0; b < 4; ++b) out.put(char((value >> (8 * b)) & 0xffu));
}

}  // namespace

void writeBinaryStl(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path, std::ios::binary);
    std::string header = "solid binary STL written by TestMesh";
    header.resize(80, ' ');
    out.write(header.data(), 80);
    putLittle32(out, std::uint32_t(mesh.triangles.size()));
    for (const auto& t : mesh.triangles) {
        const Eigen::Vector3d n = unitNormal(mesh, t);
        for (int c = 0; c < 3; ++c) putLittle32(out, std::bit_cast<std::uint32_t>(float(n[c])));
        for (const int i : t)
            for (int c = 0; c < 3; ++c) putLittle32(out, std::bit_cast<std::uint32_t>(float(mesh.vertices[i][c])));
        out.put(0).put(0);  // attribute byte count
    }
}

TriangleMesh boxMesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    TriangleMesh mesh;
    for (int c = 0; c < 8; ++c)  // corner c: bit 0 -> x, bit 1 -> y, bit 2 -> z at hi
        mesh.vertices.emplace_back(c & 1 ? hi.x() : lo.x(), c & 2 ? hi.y() : lo.y(), c & 4 ? hi.z() : lo.z());
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        mesh.triangles.push_back({q[0], q[1], q[2]});
        mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    return mesh;
}

TriangleMesh sphereMesh(const Eigen::Vector3d& centre, double radius, int rings) {
    TriangleMesh mesh;
    const int around = 2 * rings;
    mesh.vertices.push_back(centre + Eigen::Vector3d(0, 0, -radius));  // south pole
    for (int r = 1; r < rings; ++r) {
        const double theta = M_PI * r / rings;  // from the south pole
        for (int a = 0; a < around; ++a) {
            const double phi = 2 * M_PI * a / around;
            mesh.vertices.push_back(centre + radius * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                                                      std::sin(theta) * std::sin(phi),
                                                                      -std::cos(theta)));
        }
    }
    mesh.vertices.push_back(centre + Eigen::Vector3d(0, 0, radius));  // north pole
    const int north = int(mesh.vertices.size()) - 1;
    auto at = [&](int r, int a) { return 1 + (r - 1) * around + (a % around); };
    for (int a = 0; a < around; ++a) {
        mesh.triangles.push_back({0, at(1, a + 1), at(1, a)});
        mesh.triangles.push_back({north, at(rings - 1, a), at(rings - 1, a + 1)});
        for (int r = 1; r + 1 < rings; ++r) {
            mesh.triangles.push_back({at(r, a), at(r, a + 1), at(r + 1, a + 1)});
            mesh.triangles.push_back({at(r, a), at(r + 1, a + 1), at(r + 1, a)});
        }
    }
    return mesh;
}

TriangleMesh joined(const TriangleMesh& a, const TriangleMesh& b) {
    TriangleMesh out = a;
    const int shift = int(a.vertices.size());
    out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (const auto& t : b.triangles) out.triangles.push_back({t[0] + shift, t[1] + shift, t[2] + shift});
    return out;
}

void writeAsciiPly(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(9);
    out << "ply\nformat ascii 1.0\nelement vertex " << mesh.vertices.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << mesh.triangles.size()
        << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const auto& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

void writeOff(const TriangleMesh& mesh, const std::string& path) {
    std::ofstream out(path);
    out.precision(9);
    out << "OFF\n" << mesh.vertices.size() << ' ' << mesh.triangles.size() << " 0\n";
    for (const auto& p : mesh.vertices) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

}  // namespace bop::test
