// The main of the test executables without MPI.
#include "CatchRunner.hpp"

int main(int argc, char** argv) {
    return bop::test::runCatch(argc, argv);
}
