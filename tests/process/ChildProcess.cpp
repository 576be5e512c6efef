#include "process/ChildProcess.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace bop::test {
namespace {

using Clock = std::chrono::steady_clock;

const Clock::time_point kTestStart = Clock::now();

// The children alive in this test process, for the report of one that misses its deadline
// (a test may run a command on a thread of its own).
std::mutex gLiveMutex;
std::vector<ChildProcess*> gLive;

// Open MPI refuses root unless told (CI runs as root) and more ranks than cores unless told.
void allowMpiAsRoot() {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
}

std::string joined(const std::vector<std::string>& argv) {
    std::string s;
    for (const auto& a : argv) s += (s.empty() ? "" : " ") + a;
    std::replace(s.begin(), s.end(), '\n', ' ');  // a script given inline, on one line
    return s.size() > 300 ? s.substr(0, 297) + "..." : s;
}

std::string lastLines(const std::string& text, std::size_t lines) {
    std::size_t at = text.size();
    if (at > 0 && text[at - 1] == '\n') --at;
    for (std::size_t k = 0; k < lines && at != std::string::npos && at > 0; ++k) at = text.rfind('\n', at - 1);
    return at == std::string::npos || at == 0 ? text : text.substr(at + 1);
}

std::string indented(const std::string& text) {
    std::string out = "    ";
    for (const char c : text) out += c == '\n' ? std::string("\n    ") : std::string(1, c);
    while (!out.empty() && (out.back() == ' ' || out.back() == '\n')) out.pop_back();
    return out + '\n';
}

}  // namespace

double testClockS() {
    return std::chrono::duration<double>(Clock::now() - kTestStart).count();
}

ChildProcess::ChildProcess(std::vector<std::string> argv, Milliseconds deadline, const std::string& ready)
    : name_(joined(argv)), started_(Clock::now()) {
    allowMpiAsRoot();
    int pipeFds[2];
    if (pipe2(pipeFds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    std::fflush(nullptr);
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    if (pid_ == 0) {
        dup2(pipeFds[1], 1);  // dup2 clears close-on-exec on the copies
        dup2(pipeFds[1], 2);
        setpgid(0, 0);  // its own group: stop() reaches mpirun, which passes the signal on to its ranks
        // Killed with the test (by ctest's timeout, say) rather than left running: mpirun's ranks
        // go with it.
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent) _exit(127);
        std::vector<char*> args;
        for (auto& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        execvp(args[0], args.data());
        std::fprintf(stderr, "cannot run %s: %s\n", args[0], std::strerror(errno));
        _exit(127);
    }
    setpgid(pid_, pid_);  // also here, so that a signal sent at once finds the group
    close(pipeFds[1]);
    fd_ = pipeFds[0];
    fcntl(fd_, F_SETFL, O_NONBLOCK);
    {
        std::lock_guard lock(gLiveMutex);
        gLive.push_back(this);
    }
    std::printf("bop-test [%.1f s]: started pid %d: %s\n", testClockS(), pid_, name_.c_str());
    if (ready.empty()) return;
    try {
        waitFor(ready, deadline);
        if (ready == "listening on ") readEndpoint(ready, deadline);
        known_ = processTree(pid_);
    } catch (...) {  // the destructor does not run after a constructor throws
        forget();
        throw;
    }
}

void ChildProcess::readEndpoint(const std::string& after, Milliseconds deadline) {
    // The endpoint follows, up to a space or the end of the line.
    for (const auto until = Clock::now() + deadline;;) {
        const auto at = out_.find(after);
        const auto end = out_.find_first_of(" \n", at + after.size());
        if (end != std::string::npos) {
            endpoint_ = out_.substr(at + after.size(), end - at - after.size());
            return;
        }
        if (Clock::now() > until) missed("print its endpoint after '" + after + "'", deadline);
        drain(20);
    }
}

void ChildProcess::forget() {
    std::lock_guard lock(gLiveMutex);
    gLive.erase(std::remove(gLive.begin(), gLive.end(), this), gLive.end());
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
}

ChildProcess::~ChildProcess() {
    if (running() || alive(known_) > 0) {
        const std::vector<ProcessInfo> tree = killTree(pid_);
        for (const auto& p : known_)
            if (alive({p}) > 0) kill(p.pid, SIGKILL);
        std::printf("bop-test [%.1f s]: pid %d killed with its %zu processes\n", testClockS(), pid_, tree.size());
        reap();
    }
    forget();
}

void ChildProcess::reap() {
    // A killed process is gone at once unless the kernel holds it (a thread in D state on its
    // way out): then it is left as it is, said, rather than waited for without end.
    const auto until = Clock::now() + std::chrono::seconds(10);
    while (running() && Clock::now() < until) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (running())
        std::fprintf(stderr, "bop-test [%.1f s]: pid %d still there 10 s after SIGKILL; left behind:\n%s", testClockS(),
                     pid_, describeTree(pid_, false).c_str());
}

void ChildProcess::drain(int waitMs) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, waitMs) <= 0) return;
    char buf[4096];
    for (;;) {
        const ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) break;
        out_.append(buf, std::size_t(n));
        if (echo_) {
            std::fwrite(buf, 1, std::size_t(n), echo_);
            std::fflush(echo_);
        }
    }
}

bool ChildProcess::running() {
    if (status_ != -1) return false;
    int st = 0;
    if (waitpid(pid_, &st, WNOHANG) != pid_) {
        // Exited a second ago and not reaped yet: the kernel holds it on its way out (a normal
        // exit takes milliseconds). Its output and exit status are final; it is not waited for.
        const std::optional<int> exited = exitedStatus(pid_);
        if (!exited) return true;
        if (!exitSeen_) exitSeen_ = Clock::now();
        if (Clock::now() - *exitSeen_ < std::chrono::seconds(1)) return true;
        status_ = *exited;
        drain(0);
        std::printf(
            "bop-test [%.1f s]: pid %d exited (exit code %d) after %.1f s; the kernel has held it on its way "
            "out for over 1 s:\n%s  not waited for\n",
            testClockS(), pid_, code(), std::chrono::duration<double>(*exitSeen_ - started_).count(),
            describeTree(pid_, false).c_str());
        return false;
    }
    status_ = st;
    std::printf("bop-test [%.1f s]: pid %d ended (exit code %d) after %.1f s\n", testClockS(), pid_, code(),
                std::chrono::duration<double>(Clock::now() - started_).count());
    return false;
}

int ChildProcess::code() const {
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
}

void ChildProcess::waitFor(const std::string& text, Milliseconds deadline) {
    const auto until = Clock::now() + deadline;
    for (;;) {
        drain(20);
        if (out_.find(text) != std::string::npos) return;
        if (!running()) {
            drain(0);
            if (out_.find(text) != std::string::npos) return;
            missed("print '" + text + "' (it ended first, exit code " + std::to_string(code()) + ")", deadline);
        }
        if (Clock::now() > until) missed("print '" + text + "'", deadline);
    }
}

int ChildProcess::wait(Milliseconds deadline) {
    const auto until = Clock::now() + deadline;
    while (running()) {
        if (Clock::now() > until) missed("end", deadline);
        drain(20);
    }
    // What it printed last; a process it left behind may hold the pipe open, so not until EOF.
    drain(0);
    return code();
}

int ChildProcess::stop(int signal, Milliseconds deadline) {
    const std::vector<ProcessInfo> now = processTree(pid_);
    known_.insert(known_.end(), now.begin(), now.end());
    if (running()) kill(-pid_, signal);
    const auto until = Clock::now() + deadline;
    // mpirun may exit before its ranks: their ports are free only once they are gone too.
    while ((running() || alive(known_) > 0)) {
        if (Clock::now() > until)
            missed("end, with every process it started, after signal " + std::to_string(signal), deadline);
        drain(20);
    }
    drain(0);
    return code();
}

void ChildProcess::signal(int signal) {
    if (!running()) return;
    known_ = processTree(pid_);
    kill(-pid_, signal);
    std::printf("bop-test [%.1f s]: signal %d sent to pid %d\n", testClockS(), signal, pid_);
}

std::string ChildProcess::output() {
    drain(0);
    return out_;
}

std::string ChildProcess::tail(std::size_t lines) {
    drain(0);
    return lastLines(out_, lines);
}

void ChildProcess::missed(const std::string& waitingFor, Milliseconds deadline) {
    drain(0);
    char head[512];
    std::snprintf(head, sizeof head, "bop-test [%.1f s]: DEADLINE: pid %d did not %s within %.1f s\n", testClockS(),
                  pid_, waitingFor.c_str(), 1e-3 * double(deadline.count()));
    std::string report = head + ("  its command: " + name_ + "\nits process tree:\n") + describeTree(pid_, true) +
                         "its last lines of output:\n" + indented(lastLines(out_, 30));
    {
        std::lock_guard lock(gLiveMutex);
        for (ChildProcess* other : gLive)
            if (other != this && other->running())
                report += "another child still running, pid " + std::to_string(other->pid_) + ": " + other->name_ +
                          "\n" + describeTree(other->pid_, false) + "  its last lines of output:\n" +
                          indented(other->tail(15));
    }
    std::fprintf(stderr, "%s", report.c_str());
    std::fflush(stderr);
    const std::vector<ProcessInfo> tree = killTree(pid_);
    reap();
    std::snprintf(head, sizeof head, "pid %d did not %s within %.1f s; killed with its %zu processes", pid_,
                  waitingFor.c_str(), 1e-3 * double(deadline.count()), tree.size());
    throw DeadlineMissed(head + (" (" + name_ + "; the DEADLINE report above says where it was)"), report);
}

std::pair<int, std::string> runCommand(const std::string& command, Milliseconds deadline) {
    // A simple command replaces the shell (exec), so that the child is the program itself and
    // its exit is seen even while the kernel holds it (running()); its stderr joins its stdout
    // in the pipe anyway.
    std::string simple = command;
    if (simple.size() > 5 && simple.compare(simple.size() - 5, 5, " 2>&1") == 0) simple.resize(simple.size() - 5);
    const bool plain = simple.find_first_of(";|&<>$`()\n*?") == std::string::npos;
    ChildProcess child({"/bin/sh", "-c", plain ? "exec " + simple : command}, deadline, "");
    const int code = child.wait(deadline);
    return {code, child.output()};
}

}  // namespace bop::test
