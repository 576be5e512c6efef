#pragma once
// Helpers for every test: temporary folders, files written on the fly, the repository root.
#include <filesystem>
#include <functional>
#include <string>

namespace bop::test {

// A fresh folder under the system temp dir (unique per process and object), removed with its
// contents when the object dies.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& tag);
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (path / name).string(); }
};

// Writes text to a file and returns its path.
std::string writeText(const std::string& path, const std::string& text);

// The repository root (for config/ files).
std::string sourceDir();

// The message of the bop::Error that action throws, or "(no bop::Error thrown)".
std::string errorMessage(const std::function<void()>& action);

}  // namespace bop::test
