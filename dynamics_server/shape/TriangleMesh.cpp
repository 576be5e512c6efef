#include "TriangleMesh.hpp"

#include "bop/common/Error.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace bop::shape {
namespace {

std::string lowerCase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

void requireReadableFile(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) throw Error(path, "mesh file not found");
    if (std::filesystem::is_directory(status)) throw Error(path, "is a directory, a mesh file is expected");
    if (!std::ifstream(path, std::ios::binary)) throw Error(path, "cannot open mesh file for reading");
}

// Assimp reads a malformed OBJ number as an index error or as 0; check the "v x y z" lines first
// so that the message names the line.
void checkObjVertexLines(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line, keyword, token;
    for (int number = 1; std::getline(in, line); ++number) {
        std::istringstream fields(line);
        if (!(fields >> keyword) || keyword != "v") continue;
        for (int c = 0; c < 3; ++c) {
            char* end = nullptr;
            const double value = (fields >> token) ? std::strtod(token.c_str(), &end) : 0.0;
            if (end == nullptr || *end != '\0' || !std::isfinite(value))
                throw Error(path, "cannot parse OBJ file: line " + std::to_string(number) +
                                      ": 'v x y z' with three finite numbers expected, found '" + trimmed(line) + "'");
        }
    }
}

struct CornerHash {
    std::size_t operator()(const std::array<float, 3>& p) const {
        std::size_t h = 0;
        for (const float x : p) h = h * 0x9e3779b97f4a7c15ULL + std::hash<float>{}(x);
        return h;
    }
};

// A binary STL states its triangle count; Assimp reads a truncated one as no mesh at all, so
// say what is wrong: 84 header bytes, then 50 bytes a triangle.
void checkBinaryStlSize(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char head[84] = {};
    in.read(head, 84);
    const std::size_t got = std::size_t(in.gcount());
    const bool text = std::all_of(head, head + got, [](char c) {
        return std::isprint(static_cast<unsigned char>(c)) || std::isspace(static_cast<unsigned char>(c));
    });
    if (got >= 5 && lowerCase(std::string(head, 5)) == "solid" && text) return;  // ASCII (binary counts hold 0 bytes)
    const auto size = std::filesystem::file_size(path);
    std::uint32_t count = 0;
    for (int b = 3; b >= 0; --b) count = (count << 8) | static_cast<unsigned char>(head[80 + b]);
    if (got < 84 || size != 84 + 50 * std::uintmax_t(count))
        throw Error(path, "not a whole binary STL: it has " + std::to_string(size) + " bytes" +
                              (got < 84 ? std::string(", fewer than the 84 of the header")
                                        : ", but its header declares " + std::to_string(count) + " triangles, i.e. " +
                                              std::to_string(84 + 50 * std::uintmax_t(count)) + " bytes"));
}

// The extensions loadMesh reads, as Assimp lists them ("*.3ds;*.obj;...").
std::string meshExtensions() {
    std::string list;
    Assimp::Importer().GetExtensionList(list);
    return list;
}

}  // namespace

TriangleMesh loadMesh(const std::string& path) {
    requireReadableFile(path);
    const std::string extension = lowerCase(std::filesystem::path(path).extension().string());
    Assimp::Importer importer;
    if (extension.empty() || !importer.IsExtensionSupported(extension))
        throw Error(path, "unknown mesh file extension '" + extension +
                              "'; accepted are .obj, .stl, .ply, .off, .gltf, .glb and the others Assimp reads (" +
                              meshExtensions() + ")");
    if (extension == ".obj") checkObjVertexLines(path);
    if (extension == ".stl") checkBinaryStlSize(path);
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
    if (scene == nullptr) {
        const std::string why = trimmed(importer.GetErrorString());
        if (why.find("No output meshes") != std::string::npos)  // Assimp's words for a file without faces
            throw Error(path, "mesh has no triangles; a triangle surface is expected");
        throw Error(path, "cannot read the mesh file: " + why);
    }

    TriangleMesh mesh;
    std::unordered_map<std::array<float, 3>, int, CornerHash> indexOf;  // welds identical corners
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh& part = *scene->mMeshes[m];
        std::vector<int> welded(part.mNumVertices);
        for (unsigned v = 0; v < part.mNumVertices; ++v) {
            const aiVector3D& p = part.mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error(path, "vertex " + std::to_string(v + 1) + " of mesh " + std::to_string(m + 1) +
                                      " has a non-finite coordinate");
            const auto [it, added] = indexOf.emplace(std::array<float, 3>{p.x, p.y, p.z}, int(mesh.vertices.size()));
            if (added) mesh.vertices.emplace_back(p.x, p.y, p.z);
            welded[v] = it->second;
        }
        for (unsigned f = 0; f < part.mNumFaces; ++f) {
            const aiFace& face = part.mFaces[f];
            if (face.mNumIndices != 3) continue;  // points and lines: not a surface
            std::array<int, 3> tri{};
            for (int c = 0; c < 3; ++c) {
                if (face.mIndices[c] >= part.mNumVertices)
                    throw Error(path, "face " + std::to_string(f + 1) + " refers to vertex " +
                                          std::to_string(face.mIndices[c] + 1) + ", but its mesh has " +
                                          std::to_string(part.mNumVertices) + " vertices");
                tri[std::size_t(c)] = welded[face.mIndices[c]];
            }
            mesh.triangles.push_back(tri);
        }
    }
    if (mesh.triangles.empty()) throw Error(path, "mesh has no triangles; a triangle surface is expected");
    return mesh;
}

Eigen::AlignedBox3d meshBounds(const TriangleMesh& mesh) {
    Eigen::AlignedBox3d box;  // empty
    for (const auto& tri : mesh.triangles)
        for (const int index : tri) box.extend(mesh.vertices.at(std::size_t(index)));
    return box;
}

}  // namespace bop::shape
