#pragma once
// Errors that reach the user: each names where the problem is (file, key or message)
// and what was expected. Tools catch bop::Error at main() and exit non-zero.
#include <stdexcept>
#include <string>

namespace bop {

class Error : public std::runtime_error {
public:
    // where: a file path, "file: key" or a message name; what: the problem and what was expected.
    Error(std::string where, const std::string& what)
        : std::runtime_error(where.empty() ? what : where + ": " + what), where_(std::move(where)) {}
    const std::string& where() const { return where_; }

private:
    std::string where_;
};

}  // namespace bop
