#include "TestUtil.hpp"

#include "bop/common/Error.hpp"

#include <atomic>
#include <fstream>

#include <unistd.h>

namespace bop::test {

TempDir::TempDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    path = std::filesystem::temp_directory_path() /
           ("bop-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
}

std::string writeText(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    return path;
}

std::string sourceDir() {
    return BOP_SOURCE_DIR;
}

std::string errorMessage(const std::function<void()>& action) {
    try {
        action();
    } catch (const Error& e) {
        return e.what();
    }
    return "(no bop::Error thrown)";
}

}  // namespace bop::test
