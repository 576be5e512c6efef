// Catch2 runner for the decomposed-run tests: every rank runs every test; mpiexec fails when any
// rank fails. Registered with ctest at 1, 2, 3 and 4 ranks (tests/CMakeLists.txt).
#define CATCH_CONFIG_RUNNER
#include "parallel/Comm.hpp"

#include <catch2/catch.hpp>

int main(int argc, char** argv) {
    bop::parallel::MpiSession mpi(argc, argv);
    return Catch::Session().run(argc, argv);
}
