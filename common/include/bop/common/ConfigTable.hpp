#pragma once
// Typed, checked access to one table of a TOML file. Every read names the key it wants, so that
// finish() can report keys nobody asked for: an unknown key, or a known quantity written in the
// wrong unit (keys carry their unit as a suffix: voxel_size_mm, r0_voxels, period_s).
// Every error is a bop::Error naming the file and the full key and saying what was expected.
#include "bop/common/Error.hpp"

#include <Eigen/Core>
#include <toml++/toml.h>

#include <optional>
#include <set>
#include <string>
#include <vector>

namespace bop {

class ConfigTable {
public:
    // file: path shown in errors; prefix: dotted path of this table ("" for the root).
    ConfigTable(const toml::table& table, std::string file, std::string prefix);

    static toml::table parseFile(const std::string& path);  // bop::Error on a missing or bad file

    bool has(const std::string& key) const;
    double number(const std::string& key) const;
    double number(const std::string& key, double fallback) const;
    long long integer(const std::string& key) const;
    long long integer(const std::string& key, long long fallback) const;
    bool boolean(const std::string& key, bool fallback) const;
    std::string string(const std::string& key) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    // A string that must be one of `allowed`.
    std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                       const std::string& fallback) const;
    Eigen::Vector3d vec3(const std::string& key) const;
    Eigen::Vector3d vec3(const std::string& key, const Eigen::Vector3d& fallback) const;
    std::vector<double> numbers(const std::string& key) const;  // an array of numbers
    std::vector<std::string> strings(const std::string& key) const;
    ConfigTable table(const std::string& key) const;  // a required sub-table
    std::optional<ConfigTable> optionalTable(const std::string& key) const;
    std::vector<ConfigTable> tableArray(const std::string& key) const;  // [[key]] entries

    // Throws for the first key of this table that no call asked for.
    void finish() const;

    // An error about `key` of this table: "<file>: key '<prefix.key>': <what>".
    [[noreturn]] void fail(const std::string& key, const std::string& what) const;
    std::string fullKey(const std::string& key) const;
    const std::string& file() const { return file_; }
    const std::string& prefix() const { return prefix_; }
    const toml::table& raw() const { return *table_; }

private:
    const toml::node* get(const std::string& key) const;
    const toml::node& require(const std::string& key) const;

    const toml::table* table_;
    std::string file_, prefix_;
    mutable std::set<std::string> asked_;
};

}  // namespace bop
