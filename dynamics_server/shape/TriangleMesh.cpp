#include "TriangleMesh.hpp"

#include "bop/common/Error.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace bop::shape {
namespace {

using Soup = std::vector<std::array<double, 9>>;  // unwelded triangles: 3 vertices x (x, y, z), mm

std::string lowerCase(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

// Whole file as bytes; path: file to read.
std::string readFile(const std::string& path) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status)) throw Error(path, "mesh file not found");
    if (std::filesystem::is_directory(status)) throw Error(path, "is a directory, a mesh file is expected");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open mesh file for reading: ") + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(path, "error while reading the mesh file");
    return text.str();
}

// index: vertex index read from the file (0-based); vertexCount: vertices defined.
void checkIndex(const std::string& path, long long index, std::size_t vertexCount, std::size_t triangle) {
    if (index < 0 || std::size_t(index) >= vertexCount)
        throw Error(path, "triangle " + std::to_string(triangle) + " refers to " +
                              (index < 0 ? "a vertex before the first one" : "vertex " + std::to_string(index + 1)) +
                              ", but the mesh defines vertices 1 to " + std::to_string(vertexCount));
}

// tinyobjloader reads malformed numbers as 0; check "v x y z" lines first. text: the OBJ file.
void checkObjVertexLines(const std::string& path, const std::string& text) {
    std::istringstream lines(text);
    std::string line, keyword, token;
    for (int number = 1; std::getline(lines, line); ++number) {
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

TriangleMesh loadObj(const std::string& path, const std::string& text) {
    checkObjVertexLines(path, text);
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(text, "", config))  // "": material libraries are not needed
        throw Error(path, "cannot parse OBJ file: " + trimmed(reader.Error()));
    const std::string& warning = reader.Warning();
    if (warning.find("out of bounds") != std::string::npos || warning.find("invalid vertex index") != std::string::npos)
        throw Error(path, "a face refers to a vertex index out of range (" + trimmed(warning) + ")");

    TriangleMesh mesh;
    const auto& coords = reader.GetAttrib().vertices;
    for (std::size_t i = 0; i + 2 < coords.size(); i += 3) {
        const Eigen::Vector3d p(coords[i], coords[i + 1], coords[i + 2]);
        if (!p.allFinite()) throw Error(path, "vertex " + std::to_string(i / 3 + 1) + " has a non-finite coordinate");
        mesh.vertices.push_back(p);
    }
    for (const auto& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (const unsigned char faceSize : shape.mesh.num_face_vertices) {
            if (faceSize != 3)
                throw Error(path, "a face with " + std::to_string(faceSize) + " vertices could not be triangulated");
            std::array<int, 3> tri{};
            for (int c = 0; c < 3; ++c) {
                const int index = shape.mesh.indices[offset + c].vertex_index;
                checkIndex(path, index, mesh.vertices.size(), mesh.triangles.size());
                tri[c] = index;
            }
            mesh.triangles.push_back(tri);
            offset += 3;
        }
    }
    return mesh;
}

// Reads whitespace-separated tokens of an ASCII STL, tracking the line number for messages.
class TokenReader {
public:
    explicit TokenReader(const std::string& text) : text_(text) {}
    std::string next() {
        skipSpace();
        const std::size_t start = pos_;
        while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
        return text_.substr(start, pos_ - start);
    }
    void skipLine() {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    }
    bool atEnd() {
        skipSpace();
        return pos_ >= text_.size();
    }
    int line() const { return line_; }  // 1-based line of the last token

private:
    void skipSpace() {
        for (; pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_])); ++pos_)
            line_ += text_[pos_] == '\n';
    }
    const std::string& text_;
    std::size_t pos_ = 0;  // read position, bytes
    int line_ = 1;         // current line, 1-based
};

struct ParseFailure {
    std::string what;
};

void expectKeyword(TokenReader& in, const char* keyword) {
    const std::string token = in.next();
    if (lowerCase(token) != keyword)
        throw ParseFailure{"line " + std::to_string(in.line()) + ": '" + keyword + "' expected, found '" +
                           (token.empty() ? std::string("end of file") : token) + "'"};
}

double readNumber(TokenReader& in) {
    const std::string token = in.next();
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (token.empty() || *end != '\0' || !std::isfinite(value))
        throw ParseFailure{"line " + std::to_string(in.line()) + ": a finite number expected, found '" +
                           (token.empty() ? std::string("end of file") : token) + "'"};
    return value;
}

// Parses an ASCII STL ("solid ... facet normal ... outer loop vertex x3 endloop endfacet ... endsolid",
// possibly several solids). Throws ParseFailure.
Soup parseAsciiStl(const std::string& text) {
    TokenReader in(text);
    Soup soup;
    expectKeyword(in, "solid");
    in.skipLine();  // solid name
    for (;;) {
        const std::string token = lowerCase(in.next());
        if (token == "endsolid") {
            in.skipLine();
            if (in.atEnd()) return soup;
            expectKeyword(in, "solid");
            in.skipLine();
        } else if (token == "facet") {
            expectKeyword(in, "normal");
            for (int c = 0; c < 3; ++c) readNumber(in);
            expectKeyword(in, "outer");
            expectKeyword(in, "loop");
            std::array<double, 9> tri{};
            for (int v = 0; v < 3; ++v) {
                expectKeyword(in, "vertex");
                for (int c = 0; c < 3; ++c) tri[3 * v + c] = readNumber(in);
            }
            expectKeyword(in, "endloop");
            expectKeyword(in, "endfacet");
            soup.push_back(tri);
        } else {
            throw ParseFailure{"line " + std::to_string(in.line()) + ": 'facet' or 'endsolid' expected, found '" +
                               (token.empty() ? std::string("end of file") : token) + "'"};
        }
    }
}

std::uint32_t readLittle32(const std::string& bytes, std::size_t at) {
    std::uint32_t value = 0;
    for (int b = 3; b >= 0; --b) value = (value << 8) | static_cast<unsigned char>(bytes[at + b]);
    return value;
}

// Parses a binary STL: 80-byte header, uint32 count, count x (normal, 3 vertices, uint16 attribute).
Soup parseBinaryStl(const std::string& path, const std::string& bytes) {
    const std::size_t count = readLittle32(bytes, 80);
    Soup soup(count);
    for (std::size_t t = 0; t < count; ++t)
        for (int c = 0; c < 9; ++c) {
            const float value = std::bit_cast<float>(readLittle32(bytes, 84 + 50 * t + 12 + 4 * std::size_t(c)));
            if (!std::isfinite(value))
                throw Error(path,
                            "cannot parse binary STL: triangle " + std::to_string(t) + " has a non-finite coordinate");
            soup[t][c] = value;
        }
    return soup;
}

// Welds vertices with identical coordinates (exact match) so that the topology can be checked.
TriangleMesh weld(const Soup& soup) {
    TriangleMesh mesh;
    std::map<std::array<double, 3>, int> indexOf;
    for (const auto& tri : soup) {
        std::array<int, 3> ids{};
        for (int v = 0; v < 3; ++v) {
            const std::array<double, 3> key{tri[3 * v], tri[3 * v + 1], tri[3 * v + 2]};
            const auto [it, inserted] = indexOf.emplace(key, int(mesh.vertices.size()));
            if (inserted) mesh.vertices.emplace_back(key[0], key[1], key[2]);
            ids[v] = it->second;
        }
        mesh.triangles.push_back(ids);
    }
    return mesh;
}

TriangleMesh loadStl(const std::string& path, const std::string& bytes) {
    const std::size_t start = std::min(bytes.find_first_not_of(" \t\r\n"), bytes.size());
    const bool looksAscii = lowerCase(bytes.substr(start, 5)) == "solid" &&
                            (bytes.size() == start + 5 || std::isspace(static_cast<unsigned char>(bytes[start + 5])));
    const bool sizeFitsBinary = bytes.size() >= 84 && 84 + 50 * std::size_t(readLittle32(bytes, 80)) == bytes.size();
    std::string asciiProblem;  // why the ASCII parse failed
    if (looksAscii) {
        try {
            return weld(parseAsciiStl(bytes));
        } catch (const ParseFailure& failure) {
            asciiProblem = failure.what;
        }
    }
    if (sizeFitsBinary) return weld(parseBinaryStl(path, bytes));
    const std::string binaryProblem =
        bytes.size() < 84 ? "has " + std::to_string(bytes.size()) + " bytes, fewer than the 84 of a binary STL header"
                          : "declares " + std::to_string(readLittle32(bytes, 80)) + " triangles, i.e. " +
                                std::to_string(84 + 50 * std::size_t(readLittle32(bytes, 80))) +
                                " bytes, but the file has " + std::to_string(bytes.size()) + " bytes";
    if (looksAscii)
        throw Error(path,
                    "cannot parse ASCII STL: " + asciiProblem + " (nor is it a binary STL: it " + binaryProblem + ")");
    throw Error(path,
                "not an STL file: it does not start with 'solid' (ASCII STL), and as binary STL it " + binaryProblem);
}

}  // namespace

TriangleMesh loadMesh(const std::string& path) {
    const std::string extension = lowerCase(std::filesystem::path(path).extension().string());
    if (extension != ".obj" && extension != ".stl")
        throw Error(path, "unknown mesh file extension '" + extension + "'; accepted are .obj and .stl (any case)");
    const std::string bytes = readFile(path);
    TriangleMesh mesh = extension == ".obj" ? loadObj(path, bytes) : loadStl(path, bytes);
    if (mesh.triangles.empty()) throw Error(path, "mesh has no triangles; a closed triangle surface is expected");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
        for (const int index : mesh.triangles[t]) checkIndex(path, index, mesh.vertices.size(), t);
    return mesh;
}

void requireClosed(const TriangleMesh& mesh, const std::string& path) {
    if (mesh.triangles.empty()) throw Error(path, "mesh has no triangles; a closed (watertight) surface is expected");
    const std::size_t vertexCount = mesh.vertices.size();
    std::vector<std::pair<std::uint64_t, bool>> edges;  // (undirected edge key, used from lower to higher index)
    edges.reserve(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        for (const int index : tri) checkIndex(path, index, vertexCount, t);
        const Eigen::Vector3d& a = mesh.vertices[tri[0]];
        if ((mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).squaredNorm() == 0.0) continue;  // zero area
        for (int e = 0; e < 3; ++e) {
            const auto from = std::uint64_t(tri[e]), to = std::uint64_t(tri[(e + 1) % 3]);
            edges.emplace_back(from < to ? (from << 32 | to) : (to << 32 | from), from < to);
        }
    }
    std::sort(edges.begin(), edges.end());
    std::size_t boundary = 0, nonManifold = 0, misoriented = 0;
    std::uint64_t example = 0;  // key of one offending edge
    for (std::size_t first = 0; first < edges.size();) {
        std::size_t last = first, forward = 0;
        for (; last < edges.size() && edges[last].first == edges[first].first; ++last) forward += edges[last].second;
        const std::size_t uses = last - first;
        std::size_t* counter = uses == 1 ? &boundary : uses > 2 ? &nonManifold : forward != 1 ? &misoriented : nullptr;
        if (counter != nullptr) {
            if (boundary + nonManifold + misoriented == 0) example = edges[first].first;
            ++*counter;
        }
        first = last;
    }
    if (boundary + nonManifold + misoriented == 0) return;
    const Eigen::Vector3d& p = mesh.vertices[example >> 32];
    const Eigen::Vector3d& q = mesh.vertices[example & 0xffffffffu];
    std::ostringstream what;
    what << "mesh is not closed: " << boundary << " boundary edges, " << nonManifold << " non-manifold edges, "
         << misoriented << " edges whose two triangles are inconsistently oriented (e.g. the edge from (" << p.x()
         << ", " << p.y() << ", " << p.z() << ") to (" << q.x() << ", " << q.y() << ", " << q.z()
         << ") mm); a closed (watertight), consistently oriented triangle surface is expected";
    throw Error(path, what.str());
}

Eigen::AlignedBox3d meshBounds(const TriangleMesh& mesh) {
    Eigen::AlignedBox3d box;  // empty
    for (const auto& tri : mesh.triangles)
        for (const int index : tri) box.extend(mesh.vertices.at(std::size_t(index)));
    return box;
}

}  // namespace bop::shape
