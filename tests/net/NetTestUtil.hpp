#pragma once
// Helpers for the tests that run BoP's programs (net, two-host): where they are built, a server's
// command line, free ports, counts from a server's summary, the built torus, output folders.
// The processes themselves: process/ChildProcess.hpp.
#include "process/ChildProcess.hpp"

#include <string>
#include <vector>

namespace bop::test {

// The build folder's executables (BOP_BUILD_DIR), MPI launcher (BOP_MPIEXEC) and sources.
std::string buildDir();
std::string mpiexec();

// bop-server's command line at `ranks` ranks (through mpiexec, oversubscribed, above one) serving
// `scenePath` on an ephemeral port, then `extra`.
std::vector<std::string> serverCommand(int ranks, const std::string& scenePath, const std::vector<std::string>& extra);

// A base port P for `bop-server --port P` whose P, P+1 and P+2 are free on 127.0.0.1 now, outside
// the kernel's ephemeral range: a server stopped and started again on it finds its ports free.
int freeBasePort();

// A count a stopped server printed before `what` ("N malformed messages refused", "K commands"),
// or -1 if it printed none.
long long printedCount(const std::string& output, const std::string& what);

// The longest wait of a stopped server's step loop on its front ("the step loop waited on the
// front N times, longest X ms"), ms; REQUIREs the line.
double longestFrontWaitMs(const std::string& output);

// The resident memory of the bop-server processes (every rank) `server` started, MB.
double serverResidentMb(int pid);

// The torus bag as its construction timeline builds it (4,000 steps, one rank): the final.xyz of
// a batch run kept in build/test-output/built-torus/ for the test processes that follow, made
// again when bop-server, the torus scene or its mesh is newer.
const std::string& builtTorus();

// build/test-output/GROUP/NAME, emptied: where a test leaves files to look at.
std::string outputDir(const std::string& group, const std::string& name);

}  // namespace bop::test
