#pragma once
// The tests' Catch2 session (CatchRunner.cpp), for the executables' mains.
namespace bop::test {

int runCatch(int argc, char** argv);  // runs the tests the command line selects; the exit code

}  // namespace bop::test
