#pragma once
// A bop-server (or any tool that prints "listening on ENDPOINT") run as a child process for the
// integration tests: started with its arguments, its control endpoint read from its output,
// stopped by a signal, its whole output kept for assertions. A client runs the same way, waited
// for until it prints its own `ready` text.
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace bop::test {

class ServerProcess {
public:
    // Starts argv[0] with the arguments; waits up to `timeout` for `ready` in its output
    // (std::runtime_error with the output so far if it does not come). The endpoint is read
    // after "listening on ".
    ServerProcess(std::vector<std::string> argv, std::chrono::milliseconds timeout = std::chrono::seconds(60),
                  const std::string& ready = "listening on ");
    ~ServerProcess();  // SIGKILL if still running
    ServerProcess(const ServerProcess&) = delete;
    ServerProcess& operator=(const ServerProcess&) = delete;

    const std::string& endpoint() const { return endpoint_; }  // tcp://127.0.0.1:PORT
    bool running();
    // Sends `signal` to its process group and waits up to `timeout` for the exit of every process
    // in it (mpirun's ranks too: their ports are free after); returns the exit code (128 + signal
    // if killed), or -1 if some did not exit (then the group is killed). mpirun exits with 1 after
    // a SIGINT or SIGTERM however its ranks ended.
    int stop(int signal, std::chrono::milliseconds timeout = std::chrono::seconds(30));
    // Everything the process printed (stdout and stderr) so far.
    std::string output();
    int pid() const { return pid_; }

private:
    void drain(int waitMs);
    int pid_ = -1, fd_ = -1, status_ = -1;
    std::string out_, endpoint_;
};

// Runs a shell command to its end: (exit code, everything it printed).
std::pair<int, std::string> runCommand(const std::string& command);

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

// The torus bag as its construction timeline builds it (4,000 steps, one rank): the final.xyz of
// a batch run kept in build/test-output/built-torus/ for the test processes that follow, made
// again when bop-server, the torus scene or its mesh is newer.
const std::string& builtTorus();

// build/test-output/GROUP/NAME, emptied: where a test leaves files to look at.
std::string outputDir(const std::string& group, const std::string& name);

}  // namespace bop::test
