// Extended XYZ output: one frame per call, numbers in %.17g (std::to_chars with precision 17,
// the same text as printf's %.17g, locale independent) so that reading back is bit-exact.
#include "app/files/ExtendedXyz.hpp"

#include "bop/common/Error.hpp"
#include "core/Threads.hpp"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>

namespace bop::app {

namespace {

constexpr const char* kProperties = "type:S:1:pos:R:3:velo:R:3:normal:R:3:orientation:R:4:omega:R:3:id:I:1:Z:I:1";

// Every species number used in p needs a name without whitespace or quotes; every id lies below
// 2^63 (readers take ids as signed 64-bit integers).
void checkSpeciesNames(const std::string& where, const core::Particles& p,
                       const std::vector<std::string>& speciesNames) {
    for (std::uint64_t id : p.id)
        if (id >> 63)
            throw Error(where, "particle id " + std::to_string(id) +
                                   " is 2^63 or more, expected ids that fit a signed 64-bit integer");
    bool seen[256] = {};
    for (std::uint8_t s : p.species) {
        if (seen[s]) continue;
        seen[s] = true;
        if (s >= speciesNames.size() || speciesNames[s].empty())
            throw Error(where, "species number " + std::to_string(s) +
                                   " has no name, expected a non-empty name at index " + std::to_string(s) +
                                   " of the species table (" + std::to_string(speciesNames.size()) + " entries)");
        for (char c : speciesNames[s])
            if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '"' || c == '\'')
                throw Error(where, "species name '" + speciesNames[s] +
                                       "' contains whitespace or quotes, expected a single word");
    }
}

void putNumber(std::string& out, double v) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
    out.append(buf, r.ptr);
}

template <class Int>
void putInteger(std::string& out, Int v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out.append(buf, r.ptr);
}

void putTriple(std::string& out, const Eigen::Vector3d& v, char sep = ' ') {
    for (int k = 0; k < 3; ++k) {
        if (k > 0) out += sep;
        putNumber(out, v[k]);
    }
}

std::string commentLine(const XyzFrameInfo& info) {
    const Eigen::Vector3d len = info.boxHi - info.boxLo;
    std::string s = "Lattice=\"";
    putNumber(s, len.x());
    s += " 0 0 0 ";
    putNumber(s, len.y());
    s += " 0 0 0 ";
    putNumber(s, len.z());
    s += "\" Origin=\"";
    putTriple(s, info.boxLo);
    s += "\" BoxHi=\"";
    putTriple(s, info.boxHi);
    s += "\" Properties=";
    s += kProperties;
    s += " Time=";
    putNumber(s, info.time);
    s += " Step=";
    putInteger(s, info.step);
    if (!info.births.empty()) {
        s += " Births=";
        for (char b : info.births) s += b ? '1' : '0';
    }
    if (info.seeds >= 0) {
        s += " Seeds=";
        putInteger(s, info.seeds);
    }
    if (info.nextId > 0) {
        s += " NextId=";
        putInteger(s, info.nextId);
    }
    if (!info.cuts.empty()) {
        s += " Cuts=\"";
        for (const core::CutCommand& c : info.cuts) {
            if (&c != info.cuts.data()) s += ' ';
            putTriple(s, c.from);
            s += ' ';
            putTriple(s, c.to);
            s += ' ';
            putNumber(s, c.radius);
        }
        s += '"';
    }
    if (!info.yields.empty()) {
        s += " Yields=\"";
        for (const auto& group : info.yields) {
            if (&group != info.yields.data()) s += ' ';
            putInteger(s, (long long)group.size());
            for (std::uint64_t v : group) {
                s += ' ';
                putInteger(s, (long long)v);
            }
        }
        s += '"';
    }
    if (!info.settle.empty()) {
        s += " Settle=\"";
        s += info.settle;
        s += '"';
    }
    if (info.units.lengthKnown()) {
        s += " LengthUnitMm=";
        putNumber(s, info.units.lengthMm);
    }
    if (info.units.physical) {
        s += " MassUnitKg=";
        putNumber(s, info.units.massKg);
        s += " TimeUnitS=";
        putNumber(s, info.units.timeS);
        s += " ForceUnitN=";
        putNumber(s, info.units.forceN());
        s += " TimeS=";
        putNumber(s, info.units.toS(info.time));
    }
    s += " pbc=\"";
    for (int k = 0; k < 3; ++k) {
        if (k > 0) s += ' ';
        s += info.periodic[std::size_t(k)] ? 'T' : 'F';
    }
    s += "\"\n";
    return s;
}

// One particle's line.
void putLine(std::string& line, const core::Particles& p, const std::vector<std::string>& speciesNames, std::size_t i) {
    line += speciesNames[p.species[i]];
    line += ' ';
    putTriple(line, p.pos[i]);
    line += ' ';
    putTriple(line, p.vel[i]);
    line += ' ';
    putTriple(line, p.normal[i]);
    line += ' ';
    const Eigen::Quaterniond& q = p.q[i];  // OVITO's component order: x y z w
    for (double c : {q.x(), q.y(), q.z(), q.w()}) {
        putNumber(line, c);
        line += ' ';
    }
    putTriple(line, p.omega[i]);
    line += ' ';
    putInteger(line, p.id[i]);
    line += ' ';
    putInteger(line, int(p.species[i]));
    line += '\n';
}

// The lines are formatted on the threads in blocks, a group of blocks at a time (so that the
// text in memory stays near 50 MB), and written in order: the same bytes at any thread count. A
// million-particle state is about 184 MB of text, mostly numbers to 17 digits.
constexpr std::size_t kLinesPerBlock = 4096;
constexpr std::size_t kBlocksPerGroup = 64;

void writeFrame(std::ostream& os, const core::Particles& p, const std::vector<std::string>& speciesNames,
                const XyzFrameInfo& info) {
    const std::string head = std::to_string(p.size()) + "\n" + commentLine(info);
    os.write(head.data(), std::streamsize(head.size()));
    const std::size_t group = kLinesPerBlock * kBlocksPerGroup;
    std::vector<std::string> text(kBlocksPerGroup);
    for (std::size_t g0 = 0; g0 < p.size(); g0 += group) {
        const std::size_t g1 = std::min(p.size(), g0 + group);
        core::forBlocks(g1 - g0, kLinesPerBlock, [&](std::size_t b, std::size_t i0, std::size_t i1) {
            text[b].clear();
            for (std::size_t i = g0 + i0; i < g0 + i1; ++i) putLine(text[b], p, speciesNames, i);
        });
        for (std::size_t b = 0; b < core::blockCount(g1 - g0, kLinesPerBlock); ++b)
            os.write(text[b].data(), std::streamsize(text[b].size()));
    }
}

}  // namespace

void writeExtendedXyz(std::ostream& os, const core::Particles& p, const std::vector<std::string>& speciesNames,
                      const XyzFrameInfo& info) {
    checkSpeciesNames("extended XYZ output", p, speciesNames);
    writeFrame(os, p, speciesNames, info);
}

void appendExtendedXyz(const std::string& path, const core::Particles& p, const std::vector<std::string>& speciesNames,
                       const XyzFrameInfo& info) {
    checkSpeciesNames(path, p, speciesNames);
    std::ofstream out(path, std::ios::binary | std::ios::app);
    if (!out) throw Error(path, std::string("cannot write: ") + std::strerror(errno));
    writeFrame(out, p, speciesNames, info);
    out.flush();
    if (!out) throw Error(path, std::string("cannot write: ") + std::strerror(errno) + " (disk full?)");
}

}  // namespace bop::app
