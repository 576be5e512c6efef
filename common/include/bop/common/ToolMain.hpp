#pragma once
// The outer frame of every command-line tool: run it, and turn an escaping error into one line
// on stderr and a non-zero exit (2 for bad input reported as bop::Error, 1 for anything else).
#include "bop/common/Error.hpp"

#include <exception>
#include <iostream>

namespace bop {

template <class Run>
int runTool(const char* tool, Run run) {
    try {
        return run();
    } catch (const Error& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << tool << ": error: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace bop
