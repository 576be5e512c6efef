#pragma once
// Internal to the extended XYZ reader: text helpers, the comment line (key=value pairs, values
// bare or in double quotes) and the Properties column list. Errors: bop::Error(path, "line N: ...").
#include "app/files/ExtendedXyz.hpp"
#include "bop/common/Error.hpp"

#include <charconv>
#include <cmath>
#include <map>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace bop::app::xyz {

struct Column {
    std::string name;  // lower case
    char type;         // S R I L
    int count;
    int first;  // index of its first word on a particle line
};

class Reader {
public:
    explicit Reader(const std::string& path) : path_(path) {}
    [[noreturn]] void fail(long long line, const std::string& what) const {
        throw Error(path_, "line " + std::to_string(line) + ": " + what);
    }

private:
    const std::string& path_;
};

std::string_view trim(std::string_view s);
std::vector<std::string_view> splitWords(std::string_view s);
std::string lower(std::string_view s);

// The whole of s as a number (a leading '+' allowed; floating point must be finite).
template <class T>
bool parseWhole(std::string_view s, T& v) {
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size()) return false;
    if constexpr (std::is_floating_point_v<T>) return std::isfinite(v);
    return true;
}

using KeyValues = std::map<std::string, std::string>;  // key (lower case) -> value

// Comment line -> key/values (bare keys get "T").
KeyValues parseComment(const Reader& r, long long line, std::string_view s);
// Lattice/Origin/BoxHi, pbc, Time, Step.
XyzFrameInfo parseInfo(const Reader& r, long long line, const KeyValues& kv);
// The Properties key; known names must have their type and count.
std::vector<Column> parseProperties(const Reader& r, long long line, const KeyValues& kv);
const Column* findColumn(const std::vector<Column>& cols, const std::string& name);

}  // namespace bop::app::xyz
