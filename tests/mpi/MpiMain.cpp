// Catch2 runner for the decomposed-run tests: every rank runs every test; mpiexec fails when any
// rank fails. Registered with ctest at 1, 2, 3 and 4 ranks (tests/CMakeLists.txt). Catch2
// itself is CatchRunner.cpp.
#include "CatchRunner.hpp"
#include "parallel/Comm.hpp"

int main(int argc, char** argv) {
    bop::parallel::MpiSession mpi(argc, argv);
    return bop::test::runCatch(argc, argv);
}
