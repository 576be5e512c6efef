// Catch2's implementation, compiled once for every test executable; each has its own main
// (TestMain.cpp, or mpi/MpiMain.cpp with MPI around it) that calls runCatch().
#define CATCH_CONFIG_RUNNER
#include "CatchRunner.hpp"

#include <catch2/catch.hpp>

int bop::test::runCatch(int argc, char** argv) {
    return Catch::Session().run(argc, argv);
}
