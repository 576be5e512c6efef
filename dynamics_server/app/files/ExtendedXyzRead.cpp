// Extended XYZ input: finds the wanted frame (scanning counts only), then parses its comment line
// (ExtendedXyzParse) and its particle lines.
#include "app/files/ExtendedXyz.hpp"
#include "app/files/ExtendedXyzParse.hpp"
#include "bop/common/Error.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace bop::app {

namespace {

using xyz::Column;
using xyz::findColumn;
using xyz::parseWhole;
using xyz::Reader;
using xyz::splitWords;
using xyz::trim;

// The shortest-arc rotation taking e_z to the direction of n (identity for n = 0; half a turn
// about e_x for n along -e_z).
Eigen::Quaterniond shortestArcFromZ(const Eigen::Vector3d& n) {
    const double len = n.norm();
    if (!(len > 0)) return Eigen::Quaterniond::Identity();
    const Eigen::Vector3d u = n / len;
    Eigen::Quaterniond q(1 + u.z(), -u.y(), u.x(), 0);  // w = 1 + e_z.u, xyz = e_z x u
    if (q.squaredNorm() < 1e-30) return Eigen::Quaterniond(0, 1, 0, 0);
    return q.normalized();
}

struct FrameStart {
    std::streamoff offset;
    long long line;  // line number of its count line
    std::size_t count;
};

// Frame starts up to and including frame `want` (all frames for want < 0); checks every count
// line and that every frame it passes is complete. Returns the number of the last line read.
long long scanFrames(const Reader& r, std::istream& in, int want, std::vector<FrameStart>& frames) {
    long long line = 0;
    std::string s;
    while (want < 0 || int(frames.size()) <= want) {
        const std::streamoff offset = in.tellg();
        if (!std::getline(in, s)) break;
        ++line;
        const std::string_view t = trim(s);
        if (t.empty()) continue;  // blank lines between frames
        std::size_t n = 0;
        if (!parseWhole(t, n))
            r.fail(line, "'" + std::string(t.substr(0, 40)) +
                             "' is not a particle count, expected a "
                             "non-negative integer alone on the line");
        frames.push_back({offset, line, n});
        const std::string frameName = "frame " + std::to_string(frames.size() - 1);
        if (!std::getline(in, s))
            r.fail(line + 1,
                   "file ends before the comment line of " + frameName + ", expected a line with Properties=...");
        ++line;
        for (std::size_t i = 0; i < n; ++i, ++line) {
            if (in.peek() == std::char_traits<char>::eof())
                r.fail(line + 1, "file ends after " + std::to_string(i) + " particle lines of " + frameName +
                                     " (truncated), expected " + std::to_string(n));
            in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
        }
    }
    return line;
}

// Files of versions that numbered a birth (1 << 63) | (step + 1) << 32 | voxel: the same id with
// bit 62 in place of bit 63, below 2^63 and apart from every other id they hold (their seeds and
// placed particles have neither bit). Ids below 2^63 stay as they are.
std::uint64_t idOfEarlierFiles(std::uint64_t id) {
    constexpr std::uint64_t bit63 = std::uint64_t(1) << 63, bit62 = std::uint64_t(1) << 62;
    return id & bit63 ? (id & ~bit63) | bit62 : id;
}

}  // namespace

XyzFrame readExtendedXyz(const std::string& path, const std::vector<std::string>& speciesNames, int frame) {
    const Reader r(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path, std::string("cannot open for reading: ") + std::strerror(errno));
    std::vector<FrameStart> frames;
    const long long lastLine = scanFrames(r, in, frame, frames);
    if (frames.empty()) r.fail(lastLine + 1, "no frame in the file, expected a particle count line");
    if (frame < -1 || frame >= int(frames.size()))
        r.fail(lastLine, "the file ends after " + std::to_string(frames.size()) + " frames but frame " +
                             std::to_string(frame) + " was asked for, expected -1 or 0.." +
                             std::to_string(frames.size() - 1));
    const FrameStart& fs = frame < 0 ? frames.back() : frames[std::size_t(frame)];
    in.clear();
    in.seekg(fs.offset);
    std::string s;
    std::getline(in, s);
    long long line = fs.line + 1;
    std::getline(in, s);
    const auto kv = parseComment(r, line, s);
    XyzFrame out;
    out.info = parseInfo(r, line, kv);
    const auto cols = parseProperties(r, line, kv);
    const Column* pos = findColumn(cols, "pos");
    // Names: a string column `type` (what the writer writes) or `species` (earlier files); numbers
    // otherwise: `Z`, an integer `type`, or `species_number`.
    const Column* species = nullptr;
    const Column* type = nullptr;
    for (const char* name : {"type", "species"})
        if (const Column* c = findColumn(cols, name); c && c->type == 'S' && !species) species = c;
    for (const char* name : {"z", "type", "species_number"})
        if (const Column* c = findColumn(cols, name); c && c->type == 'I' && !type) type = c;
    if (species) type = nullptr;
    const Column* velo = findColumn(cols, "velo");
    const Column* normal = findColumn(cols, "normal");
    const Column* orient = findColumn(cols, "orientation");
    const Column* omega = findColumn(cols, "omega");
    const Column* id = findColumn(cols, "id");
    if (!pos) r.fail(line, "Properties has no pos column, expected pos:R:3");
    if (!species && !type)
        r.fail(line,
               "Properties has no species column, expected type:S:1 or species:S:1 (names), or Z:I:1 or "
               "type:I:1 (numbers)");
    const std::size_t width = std::size_t(cols.back().first + cols.back().count);

    std::map<std::string, int, std::less<>> numberOf;
    std::string known;
    for (std::size_t k = 0; k < speciesNames.size() && k < 256; ++k)
        if (!speciesNames[k].empty()) {
            numberOf.emplace(speciesNames[k], int(k));
            known += (known.empty() ? "" : ", ") + speciesNames[k];
        }

    core::Particles& p = out.particles;
    p.resize(fs.count);
    for (std::size_t i = 0; i < fs.count; ++i) {
        ++line;
        std::getline(in, s);
        const auto w = splitWords(s);
        if (w.size() != width)
            r.fail(line, "has " + std::to_string(w.size()) + " columns, expected " + std::to_string(width) +
                             " (Properties=" + kv.at("properties") + ")");
        auto num = [&](const Column* c, int k) {
            double v = 0;
            const std::string_view word = w[std::size_t(c->first + k)];
            if (!parseWhole(word, v)) r.fail(line, c->name + " has '" + std::string(word) + "', expected a number");
            return v;
        };
        auto vec = [&](const Column* c) { return Eigen::Vector3d(num(c, 0), num(c, 1), num(c, 2)); };
        if (species) {
            const std::string_view name = w[std::size_t(species->first)];
            const auto sp = numberOf.find(name);
            if (sp == numberOf.end())
                r.fail(line, "unknown species '" + std::string(name) + "', expected one of: " + known);
            p.species[i] = std::uint8_t(sp->second);
        } else {
            int t = -1;
            const std::string_view word = w[std::size_t(type->first)];
            if (!parseWhole(word, t) || t < 0 || t >= int(std::min<std::size_t>(speciesNames.size(), 256)) ||
                speciesNames[std::size_t(t)].empty())
                r.fail(line, type->name + " '" + std::string(word) +
                                 "' is no species number, expected the number of one of: " + known);
            p.species[i] = std::uint8_t(t);
        }
        p.id[i] = i;
        if (id) {
            const std::string_view word = w[std::size_t(id->first)];
            if (!parseWhole(word, p.id[i]))
                r.fail(line, "id '" + std::string(word) + "', expected a non-negative integer");
            p.id[i] = idOfEarlierFiles(p.id[i]);
        }
        p.pos[i] = vec(pos);
        p.vel[i] = velo ? vec(velo) : Eigen::Vector3d::Zero();
        p.omega[i] = omega ? vec(omega) : Eigen::Vector3d::Zero();
        p.force[i].setZero();
        p.torque[i].setZero();
        Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
        if (orient) {
            q = Eigen::Quaterniond(num(orient, 3), num(orient, 0), num(orient, 1), num(orient, 2));  // file: x y z w
            const double norm = q.norm();
            if (!(norm > 0)) r.fail(line, "orientation is zero, expected a unit quaternion x y z w");
            if (std::abs(norm - 1) > 1e-10) q.coeffs() /= norm;
        } else if (normal) {
            q = shortestArcFromZ(vec(normal));
        }
        p.q[i] = q;
        p.normal[i] = q * Eigen::Vector3d::UnitZ();
    }
    return out;
}

}  // namespace bop::app
