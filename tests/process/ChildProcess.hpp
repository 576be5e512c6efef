#pragma once
// A process a test starts (a bop-server, mpirun, a client, a shell command), with a deadline on
// every wait. It runs in a process group of its own with its output (stdout and stderr) kept for
// assertions. Each start and end is printed with the test's clock, so a test's log says where it
// got to. A wait that passes its deadline prints, at once and flushed, what it was waiting for,
// the process tree with each process's state and wait channel (and stacks where gdb is
// installed), the last lines of this child's output and of every other child the test still
// runs; then it kills the whole tree and throws DeadlineMissed: the test fails in seconds, not at
// ctest's timeout.
#include "process/ProcessTree.hpp"

#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace bop::test {

using Milliseconds = std::chrono::milliseconds;

// A wait past its deadline: what() says which child and what it waited for; report is all that
// was printed of it (the process tree, the last lines of output of it and of the other children).
struct DeadlineMissed : std::runtime_error {
    DeadlineMissed(const std::string& what, std::string fullReport)
        : std::runtime_error(what), report(std::move(fullReport)) {}
    std::string report;
};

class ChildProcess {
public:
    // Starts argv[0] with the arguments; waits up to `deadline` for `ready` in its output (none
    // when `ready` is empty). With the default `ready`, the endpoint is what follows it.
    ChildProcess(std::vector<std::string> argv, Milliseconds deadline = std::chrono::seconds(60),
                 const std::string& ready = "listening on ");
    ~ChildProcess();  // the whole tree killed if still running
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;

    const std::string& endpoint() const { return endpoint_; }  // tcp://HOST:PORT
    bool running();
    // Waits up to `deadline` for `text` in its output (DeadlineMissed if it does not come, or if
    // the process ends first: then waitingFor says so).
    void waitFor(const std::string& text, Milliseconds deadline);
    // Waits up to `deadline` for it to end by itself; its exit code (128 + signal if killed).
    int wait(Milliseconds deadline);
    // Sends `signal` to its process group and waits up to `deadline` for the exit of every process
    // of its tree (mpirun's ranks too: their ports are free after); the exit code (128 + signal if
    // killed). mpirun exits with 1 after a SIGINT or SIGTERM however its ranks ended.
    int stop(int signal, Milliseconds deadline = std::chrono::seconds(30));
    // Sends `signal` to its process group and goes on: for a test that kills a client and
    // watches what others make of it, not how soon the kernel lets the client go (the destructor
    // waits for that, up to 10 s, without failing the test).
    void signal(int signal);
    // Everything the process printed (stdout and stderr) so far.
    std::string output();
    int pid() const { return pid_; }
    // From now on, each piece of output is also written to `to` as it comes (bop-deadline).
    void echoTo(std::FILE* to) { echo_ = to; }
    // The last `lines` lines of its output.
    std::string tail(std::size_t lines);
    const std::string& name() const { return name_; }

private:
    void drain(int waitMs);
    void readEndpoint(const std::string& after, Milliseconds deadline);
    void forget();  // out of the list of live children; the pipe closed
    void reap();    // after SIGKILL: waits up to 10 s for it to go
    [[noreturn]] void missed(const std::string& waitingFor, Milliseconds deadline);
    int code() const;
    int pid_ = -1, fd_ = -1, status_ = -1;
    std::string name_, out_, endpoint_;
    std::chrono::steady_clock::time_point started_;
    std::vector<ProcessInfo> known_;  // its tree when last looked at: ranks outlive mpirun for a moment
    std::optional<std::chrono::steady_clock::time_point> exitSeen_;  // when it was first seen to have exited
    std::FILE* echo_ = nullptr;
};

// Runs a shell command to its end, waiting up to `deadline`: (exit code, everything it printed).
std::pair<int, std::string> runCommand(const std::string& command, Milliseconds deadline);

// Seconds since the test process started, for its progress lines.
double testClockS();

}  // namespace bop::test
