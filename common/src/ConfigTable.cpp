#include "bop/common/ConfigTable.hpp"

#include <filesystem>
#include <map>
#include <sstream>

namespace bop {
namespace {

const char* typeName(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::string:
            return "a string";
        case toml::node_type::integer:
            return "an integer";
        case toml::node_type::floating_point:
            return "a number";
        case toml::node_type::boolean:
            return "a boolean";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::table:
            return "a table";
        default:
            return "a date or time";
    }
}

// Unit suffixes a key may carry, with the word used in messages.
const std::map<std::string, std::string>& unitWords() {
    static const std::map<std::string, std::string> m = {
        {"mm", "millimetres"}, {"cm", "centimetres"},  {"m", "metres"},        {"um", "micrometres"},
        {"in", "inches"},      {"voxels", "voxels"},   {"voxel", "voxels"},    {"r0", "multiples of r0"},
        {"s", "seconds"},      {"ms", "milliseconds"}, {"us", "microseconds"}, {"hz", "hertz"},
        {"khz", "kilohertz"},  {"steps", "steps"},     {"deg", "degrees"},     {"rad", "radians"},
        {"ml", "millilitres"}, {"mmhg", "mmHg"},       {"kpa", "kilopascals"}};
    return m;
}

// Split "voxel_size_mm" into ("voxel_size", "mm") when the suffix is a unit.
std::pair<std::string, std::string> splitUnit(const std::string& key) {
    const auto pos = key.rfind('_');
    if (pos == std::string::npos) return {key, ""};
    const std::string unit = key.substr(pos + 1);
    if (!unitWords().count(unit)) return {key, ""};
    return {key.substr(0, pos), unit};
}

}  // namespace

ConfigTable::ConfigTable(const toml::table& table, std::string file, std::string prefix)
    : table_(&table), file_(std::move(file)), prefix_(std::move(prefix)) {}

toml::table ConfigTable::parseFile(const std::string& path) {
    if (!std::filesystem::exists(path)) throw Error(path, "file not found (expected a TOML scene file)");
    try {
        return toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << "line " << e.source().begin.line << ", column " << e.source().begin.column << ": " << e.description()
           << " (expected valid TOML)";
        throw Error(path, os.str());
    }
}

std::string ConfigTable::fullKey(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
}

void ConfigTable::fail(const std::string& key, const std::string& what) const {
    throw Error(file_, "key '" + fullKey(key) + "': " + what);
}

const toml::node* ConfigTable::get(const std::string& key) const {
    asked_.insert(key);
    return table_->get(key);
}

const toml::node& ConfigTable::require(const std::string& key) const {
    const toml::node* n = get(key);
    if (!n) fail(key, "missing (this key is required)");
    return *n;
}

bool ConfigTable::has(const std::string& key) const {
    return get(key) != nullptr;
}

double ConfigTable::number(const std::string& key) const {
    const toml::node& n = require(key);
    if (auto v = n.value<double>(); v && (n.is_floating_point() || n.is_integer())) return *v;
    fail(key, std::string("expected a number, got ") + typeName(n));
}

double ConfigTable::number(const std::string& key, double fallback) const {
    return has(key) ? number(key) : fallback;
}

long long ConfigTable::integer(const std::string& key) const {
    const toml::node& n = require(key);
    if (n.is_integer()) return *n.value<long long>();
    fail(key, std::string("expected an integer, got ") + typeName(n));
}

long long ConfigTable::integer(const std::string& key, long long fallback) const {
    return has(key) ? integer(key) : fallback;
}

bool ConfigTable::boolean(const std::string& key, bool fallback) const {
    const toml::node* n = get(key);
    if (!n) return fallback;
    if (n->is_boolean()) return *n->value<bool>();
    fail(key, std::string("expected true or false, got ") + typeName(*n));
}

std::string ConfigTable::string(const std::string& key) const {
    const toml::node& n = require(key);
    if (n.is_string()) return *n.value<std::string>();
    fail(key, std::string("expected a string, got ") + typeName(n));
}

std::string ConfigTable::string(const std::string& key, const std::string& fallback) const {
    return has(key) ? string(key) : fallback;
}

std::string ConfigTable::choice(const std::string& key, const std::vector<std::string>& allowed,
                                const std::string& fallback) const {
    const std::string s = string(key, fallback);
    for (const auto& a : allowed)
        if (a == s) return s;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + ("'" + a + "'");
    fail(key, "'" + s + "' is not one of " + list);
}

std::vector<double> ConfigTable::numbers(const std::string& key) const {
    const toml::node& n = require(key);
    const toml::array* arr = n.as_array();
    if (!arr) fail(key, std::string("expected an array of numbers, got ") + typeName(n));
    std::vector<double> out;
    for (const toml::node& e : *arr) {
        if (!(e.is_integer() || e.is_floating_point()))
            fail(key, std::string("expected an array of numbers, found ") + typeName(e) + " in it");
        out.push_back(*e.value<double>());
    }
    return out;
}

std::vector<std::string> ConfigTable::strings(const std::string& key) const {
    const toml::node& n = require(key);
    const toml::array* arr = n.as_array();
    if (!arr) fail(key, std::string("expected an array of strings, got ") + typeName(n));
    std::vector<std::string> out;
    for (const toml::node& e : *arr) {
        if (!e.is_string()) fail(key, std::string("expected an array of strings, found ") + typeName(e) + " in it");
        out.push_back(*e.value<std::string>());
    }
    return out;
}

Eigen::Vector3d ConfigTable::vec3(const std::string& key) const {
    const std::vector<double> v = numbers(key);
    if (v.size() != 3) fail(key, "expected 3 numbers [x, y, z], got " + std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

Eigen::Vector3d ConfigTable::vec3(const std::string& key, const Eigen::Vector3d& fallback) const {
    return has(key) ? vec3(key) : fallback;
}

ConfigTable ConfigTable::table(const std::string& key) const {
    const toml::node& n = require(key);
    if (!n.is_table()) fail(key, std::string("expected a table, got ") + typeName(n));
    return ConfigTable(*n.as_table(), file_, fullKey(key));
}

std::optional<ConfigTable> ConfigTable::optionalTable(const std::string& key) const {
    if (!has(key)) return std::nullopt;
    return table(key);
}

std::vector<ConfigTable> ConfigTable::tableArray(const std::string& key) const {
    const toml::node& n = require(key);
    const toml::array* arr = n.as_array();
    if (!arr || !arr->is_array_of_tables())
        fail(key, std::string("expected an array of tables ([[") + fullKey(key) + "]]), got " + typeName(n));
    std::vector<ConfigTable> out;
    for (std::size_t i = 0; i < arr->size(); ++i)
        out.emplace_back(*(*arr)[i].as_table(), file_, fullKey(key) + "[" + std::to_string(i) + "]");
    return out;
}

void ConfigTable::finish() const {
    for (const auto& [k, node] : *table_) {
        const std::string key(k.str());
        if (asked_.count(key)) continue;
        const auto [base, unit] = splitUnit(key);
        for (const auto& wanted : asked_) {
            const auto [wbase, wunit] = splitUnit(wanted);
            if (!unit.empty() && !wunit.empty() && wbase == base)
                fail(key, "unit '" + unit + "' is not accepted here; this quantity is in " + unitWords().at(wunit) +
                              ": write '" + wanted + "'");
            if (unit.empty() && !wunit.empty() && wbase == key)
                fail(key,
                     "the unit is missing; this quantity is in " + unitWords().at(wunit) + ": write '" + wanted + "'");
        }
        std::string known;
        for (const auto& a : asked_) known += (known.empty() ? "" : ", ") + a;
        fail(key, "unknown key (known keys here: " + known + ")");
    }
}

}  // namespace bop
