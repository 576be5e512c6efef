// Extended XYZ reader, text level: words, the comment line and the Properties key.
#include "app/files/ExtendedXyzParse.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

namespace bop::app::xyz {

std::string_view trim(std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string_view::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::vector<std::string_view> splitWords(std::string_view s) {
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (true) {
        i = s.find_first_not_of(" \t\r\n", i);
        if (i == std::string_view::npos) return words;
        const std::size_t e = std::min(s.find_first_of(" \t\r\n", i), s.size());
        words.push_back(s.substr(i, e - i));
        i = e;
    }
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

namespace {

std::vector<double> parseNumbers(const Reader& r, long long line, const std::string& key, const std::string& value,
                                 std::size_t expected) {
    const auto words = splitWords(value);
    std::vector<double> v(words.size());
    for (std::size_t k = 0; k < words.size(); ++k)
        if (!parseWhole(words[k], v[k])) r.fail(line, key + " has '" + std::string(words[k]) + "', expected a number");
    if (v.size() != expected)
        r.fail(line, key + " has " + std::to_string(v.size()) + " numbers, expected " + std::to_string(expected));
    return v;
}

}  // namespace

KeyValues parseComment(const Reader& r, long long line, std::string_view s) {
    KeyValues kv;
    std::size_t i = 0;
    while ((i = s.find_first_not_of(" \t\r\n", i)) != std::string_view::npos) {
        const std::size_t keyEnd = std::min(s.find_first_of("= \t\r\n", i), s.size());
        std::string key = lower(s.substr(i, keyEnd - i));
        i = keyEnd;
        if (i >= s.size() || s[i] != '=') {
            kv[key] = "T";
            continue;
        }
        ++i;
        if (i < s.size() && s[i] == '"') {
            const std::size_t close = s.find('"', i + 1);
            if (close == std::string_view::npos)
                r.fail(line, "value of " + key + " has no closing quote, expected key=\"value\"");
            kv[key] = std::string(s.substr(i + 1, close - i - 1));
            i = close + 1;
        } else {
            const std::size_t e = std::min(s.find_first_of(" \t\r\n", i), s.size());
            kv[key] = std::string(s.substr(i, e - i));
            i = e;
        }
    }
    return kv;
}

XyzFrameInfo parseInfo(const Reader& r, long long line, const KeyValues& kv) {
    XyzFrameInfo info;
    const auto lattice = kv.find("lattice");
    if (lattice != kv.end()) {
        const auto m = parseNumbers(r, line, "Lattice", lattice->second, 9);
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (a != b && m[std::size_t(3 * a + b)] != 0)
                    r.fail(line, "Lattice is not orthogonal, expected \"Lx 0 0 0 Ly 0 0 0 Lz\"");
        info.periodic = {true, true, true};
        if (auto o = kv.find("origin"); o != kv.end()) {
            const auto v = parseNumbers(r, line, "Origin", o->second, 3);
            info.boxLo = {v[0], v[1], v[2]};
        }
        info.boxHi = info.boxLo + Eigen::Vector3d(m[0], m[4], m[8]);
        if (auto h = kv.find("boxhi"); h != kv.end()) {
            const auto v = parseNumbers(r, line, "BoxHi", h->second, 3);
            info.boxHi = {v[0], v[1], v[2]};
        }
    }
    if (auto pbc = kv.find("pbc"); pbc != kv.end()) {
        const auto words = splitWords(pbc->second);
        if (words.size() != 3)
            r.fail(line, "pbc has " + std::to_string(words.size()) + " flags, expected \"T/F T/F T/F\"");
        for (std::size_t k = 0; k < 3; ++k) {
            const std::string w = lower(words[k]);
            if (w == "t" || w == "true" || w == "1")
                info.periodic[k] = true;
            else if (w == "f" || w == "false" || w == "0")
                info.periodic[k] = false;
            else
                r.fail(line, "pbc has '" + std::string(words[k]) + "', expected T or F");
        }
    }
    if (auto t = kv.find("time"); t != kv.end() && !parseWhole(std::string_view(t->second), info.time))
        r.fail(line, "Time=" + t->second + ", expected a number");
    if (auto st = kv.find("step"); st != kv.end() && !parseWhole(std::string_view(st->second), info.step))
        r.fail(line, "Step=" + st->second + ", expected an integer");
    if (auto b = kv.find("births"); b != kv.end()) {
        for (char c : b->second) {
            if (c != '0' && c != '1') r.fail(line, "Births=" + b->second + ", expected one 0 or 1 per species");
            info.births.push_back(c == '1');
        }
    }
    if (auto sd = kv.find("seeds");
        sd != kv.end() && (!parseWhole(std::string_view(sd->second), info.seeds) || info.seeds < 0))
        r.fail(line, "Seeds=" + sd->second + ", expected a count of 0 or more");
    if (auto n = kv.find("nextid");
        n != kv.end() && (!parseWhole(std::string_view(n->second), info.nextId) || info.nextId < 1))
        r.fail(line, "NextId=" + n->second + ", expected an id of 1 or more");
    if (auto st = kv.find("settle"); st != kv.end()) info.settle = st->second;
    if (auto c = kv.find("cuts"); c != kv.end()) {
        const auto words = splitWords(c->second);
        std::vector<double> x(words.size());
        bool ok = words.size() % 7 == 0;
        for (std::size_t k = 0; ok && k < words.size(); ++k) ok = parseWhole(words[k], x[k]) && std::isfinite(x[k]);
        for (std::size_t k = 0; ok && k < words.size(); k += 7) {
            ok = x[k + 6] > 0;
            info.cuts.push_back({{x[k], x[k + 1], x[k + 2]}, {x[k + 3], x[k + 4], x[k + 5]}, x[k + 6]});
        }
        if (!ok)
            r.fail(line, "Cuts=\"" + c->second.substr(0, 80) +
                             "\", expected seven finite numbers per cut (from, to, a radius above 0)");
    }
    if (auto y = kv.find("yields"); y != kv.end()) {
        const auto words = splitWords(y->second);
        bool ok = true;
        for (std::size_t k = 0; ok && k < words.size();) {
            long long n = 0;
            ok = parseWhole(words[k++], n) && n > 0 && k + std::size_t(n) <= words.size();
            std::vector<std::uint64_t> group;
            for (long long d = 0; ok && d < n; ++d) {
                long long v = -1;
                ok = parseWhole(words[k++], v) && v >= 0 && (group.empty() || std::uint64_t(v) > group.back());
                group.push_back(std::uint64_t(v));
            }
            info.yields.push_back(std::move(group));
        }
        if (!ok)
            r.fail(line, "Yields=\"" + y->second.substr(0, 80) +
                             "\", expected groups of a count and that many voxel indices, rising");
    }
    return info;
}

std::vector<Column> parseProperties(const Reader& r, long long line, const KeyValues& kv) {
    const auto it = kv.find("properties");
    if (it == kv.end()) r.fail(line, "no Properties key, expected e.g. Properties=species:S:1:pos:R:3");
    std::vector<std::string> f;
    for (std::size_t b = 0, e; b <= it->second.size(); b = e + 1) {
        e = std::min(it->second.find(':', b), it->second.size());
        f.push_back(it->second.substr(b, e - b));
    }
    if (f.size() % 3 != 0)
        r.fail(line, "Properties=" + it->second + " is not name:type:count triples, expected e.g. species:S:1:pos:R:3");
    // The columns read, with their type and count; `type` holds names (S) or numbers (I).
    static const std::map<std::string, std::pair<std::string, int>> known = {
        {"species", {"S", 1}}, {"type", {"SI", 1}}, {"species_number", {"I", 1}}, {"z", {"I", 1}},
        {"pos", {"R", 3}},     {"velo", {"R", 3}},  {"normal", {"R", 3}},         {"orientation", {"R", 4}},
        {"omega", {"R", 3}},   {"id", {"I", 1}}};
    std::vector<Column> cols;
    int first = 0;
    for (std::size_t k = 0; k < f.size(); k += 3) {
        Column c{lower(f[k]), f[k + 1].size() == 1 ? f[k + 1][0] : '?', 0, first};
        if (c.name.empty() || std::string_view("SRIL").find(c.type) == std::string_view::npos ||
            !parseWhole(std::string_view(f[k + 2]), c.count) || c.count < 1 || c.count > 1000)
            r.fail(line, "property '" + f[k] + ":" + f[k + 1] + ":" + f[k + 2] +
                             "' is malformed, expected name:type:count with type S, R, I or L");
        if (auto kn = known.find(c.name);
            kn != known.end() && (kn->second.first.find(c.type) == std::string::npos || kn->second.second != c.count)) {
            std::string want;
            for (char t : kn->second.first)
                want += (want.empty() ? "" : " or ") + f[k] + ":" + t + ":" + std::to_string(kn->second.second);
            r.fail(line, "property " + f[k] + " is " + f[k + 1] + ":" + f[k + 2] + ", expected " + want);
        }
        first += c.count;
        cols.push_back(c);
    }
    return cols;
}

const Column* findColumn(const std::vector<Column>& cols, const std::string& name) {
    for (const Column& c : cols)
        if (c.name == name) return &c;
    return nullptr;
}

}  // namespace bop::app::xyz
