// Catch2's implementation, compiled once for every test executable; each has its own main
// (TestMain.cpp, or mpi/MpiMain.cpp with MPI around it) that calls runCatch().
#define CATCH_CONFIG_RUNNER
#include "CatchRunner.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <iostream>

int bop::test::runCatch(int argc, char** argv) {
    // Whatever a test printed is out before the next line: a test killed by ctest's timeout
    // leaves its log (stdout is a pipe under ctest, fully buffered otherwise).
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    std::cout.setf(std::ios::unitbuf);
    return Catch::Session().run(argc, argv);
}
