#include "process/ProcessTree.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

namespace bop::test {
namespace {

namespace fs = std::filesystem;

std::string readFirstLine(const fs::path& p) {
    std::ifstream in(p);
    std::string line;
    std::getline(in, line);
    return line;
}

double uptimeS() {
    double s = 0;
    std::ifstream("/proc/uptime") >> s;
    return s;
}

// Fields of /proc/PID/stat (or .../task/TID/stat) after the command name, which may hold spaces.
struct Stat {
    char state = '?';
    long ppid = 0, pgid = 0;
    unsigned long flags = 0;  // the kernel's PF_* flags
    unsigned long long utime = 0, stime = 0, start = 0;
    int exitCode = 0;  // as waitpid gives it, once it exited (readable by root)
};
constexpr unsigned long kPfExiting = 0x4;  // PF_EXITING: it called exit; the kernel is taking it down

bool readStat(const fs::path& file, Stat& s) {
    const std::string text = readFirstLine(file);
    const auto close = text.rfind(')');
    if (close == std::string::npos) return false;
    std::istringstream rest(text.substr(close + 2));
    const std::vector<std::string> f{std::istream_iterator<std::string>(rest), std::istream_iterator<std::string>()};
    if (f.size() < 20) return false;  // proc(5): state ppid pgrp ... utime (12th) stime ... starttime (20th)
    s.state = f[0][0];
    s.ppid = std::stol(f[1]);
    s.pgid = std::stol(f[2]);
    s.flags = std::stoul(f[6]);
    s.utime = std::stoull(f[11]);
    s.stime = std::stoull(f[12]);
    s.start = std::stoull(f[19]);
    if (f.size() > 49) s.exitCode = std::stoi(f[49]);  // proc(5): exit_code, the 52nd field
    return true;
}

std::string commandLine(const fs::path& dir) {
    std::ifstream in(dir / "cmdline", std::ios::binary);
    std::string c{std::istreambuf_iterator<char>(in), {}};
    std::replace(c.begin(), c.end(), '\0', ' ');
    while (!c.empty() && c.back() == ' ') c.pop_back();
    if (c.size() > 160) c = c.substr(0, 157) + "...";
    return c.empty() ? "[" + readFirstLine(dir / "comm") + "]" : c;
}

// "S futex_wait_queue x3, R x1": its threads grouped by state and wait channel.
std::string threadSummary(const fs::path& dir) {
    std::map<std::string, int> counts;
    std::error_code ec;
    for (const auto& t : fs::directory_iterator(dir / "task", ec)) {
        Stat s;
        if (!readStat(t.path() / "stat", s)) continue;
        const std::string w = readFirstLine(t.path() / "wchan");
        ++counts[std::string(1, s.state) + (w.empty() || w == "0" ? "" : " " + w)];
    }
    std::string out;
    for (const auto& [what, n] : counts) out += (out.empty() ? "" : ", ") + what + " x" + std::to_string(n);
    return out;
}

std::vector<ProcessInfo> allProcesses() {
    std::vector<ProcessInfo> all;
    const double ticks = double(sysconf(_SC_CLK_TCK)), now = uptimeS();
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc", ec)) {
        const std::string name = e.path().filename().string();
        if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
        Stat s;
        if (!readStat(e.path() / "stat", s)) continue;
        ProcessInfo p;
        p.pid = pid_t(std::stol(name));
        p.ppid = pid_t(s.ppid);
        p.pgid = pid_t(s.pgid);
        p.state = s.state;
        p.start = s.start;
        p.ageS = now - double(s.start) / ticks;
        p.cpuS = double(s.utime + s.stime) / ticks;
        all.push_back(p);
    }
    return all;
}

void fillDetails(ProcessInfo& p) {
    const fs::path dir = "/proc/" + std::to_string(p.pid);
    p.wchan = readFirstLine(dir / "wchan");
    if (p.wchan == "0") p.wchan.clear();
    p.threads = threadSummary(dir);
    p.command = commandLine(dir);
}

using Clock = std::chrono::steady_clock;

// `argv`'s standard output, read until it ends or until `until`, whichever comes first. A helper
// is never waited for past that: the kernel can hold a new process in uninterruptible sleep
// while it maps its program (a page-reclaim thread holding the file's mapping lock), and a
// report that waited for it would hang the test it reports on. Past `until` the helper is
// killed and left to the kernel; what it printed is returned with a line saying so.
std::string outputWithin(std::vector<std::string> argv, Clock::time_point until) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) return "";
    const pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]), close(fds[1]);
        return "";
    }
    if (pid == 0) {
        setpgid(0, 0);
        dup2(fds[1], 1);
        const int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, 2);
        std::vector<char*> args;
        for (auto& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        execvp(args[0], args.data());
        _exit(127);
    }
    close(fds[1]);
    std::string out;
    bool ended = false;
    for (char buf[4096]; Clock::now() < until;) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
        pollfd p{fds[0], POLLIN, 0};
        if (poll(&p, 1, int(std::max<long long>(1, left))) <= 0) continue;
        const ssize_t n = read(fds[0], buf, sizeof buf);
        if (n <= 0) {
            ended = true;
            break;
        }
        out.append(buf, std::size_t(n));
    }
    close(fds[0]);
    if (!ended) {
        kill(-pid, SIGKILL);
        out += "(" + argv[0] + " gave no answer in time; left to the kernel)\n";
    }
    waitpid(pid, nullptr, WNOHANG);  // reaped now if it is gone; otherwise left as a zombie, harmlessly
    return out;
}

bool onPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');)
        if (!dir.empty() && access((dir + "/" + program).c_str(), X_OK) == 0) return true;
    return false;
}

// Each thread's first frames (gdb), by `until`.
std::string stacksOf(pid_t pid, Clock::time_point until) {
    static const bool haveGdb = onPath("gdb");
    if (!haveGdb) return "";
    const std::string all =
        outputWithin({"gdb", "-p", std::to_string(pid), "-batch", "-ex", "thread apply all bt 12"}, until);
    std::istringstream lines(all);
    std::string out;
    for (std::string line; std::getline(lines, line);)
        if (line.rfind("Thread", 0) == 0 || line.rfind("#", 0) == 0 || line.rfind("(gdb gave", 0) == 0)
            out += line + "\n";
    return out;
}

// The kernel's stack of each thread in uninterruptible sleep (D): where the kernel holds it
// (root only; nothing where /proc/PID/task/TID/stack cannot be read).
std::vector<std::string> kernelStacksOfBlockedThreads(pid_t pid) {
    std::vector<std::string> stacks;
    std::error_code ec;
    for (const auto& t : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
        Stat s;
        if (!readStat(t.path() / "stat", s) || s.state != 'D') continue;
        std::ifstream in(t.path() / "stack");
        std::string text = "      kernel stack of thread " + t.path().filename().string() + " (D):\n";
        int lines = 0;
        for (std::string line; lines < 16 && std::getline(in, line); ++lines) text += "        " + line + "\n";
        stacks.push_back(text);
    }
    return stacks;
}

}  // namespace

std::vector<ProcessInfo> processTree(pid_t root) {
    const std::vector<ProcessInfo> all = allProcesses();
    std::vector<ProcessInfo> tree;
    pid_t group = 0;
    for (const auto& p : all)
        if (p.pid == root) tree.push_back(p), group = p.pgid;
    if (tree.empty()) return tree;
    // Descendants, breadth first; then members of root's group that are not among them.
    for (std::size_t k = 0; k < tree.size(); ++k)
        for (const auto& p : all)
            if (p.ppid == tree[k].pid && p.pid != root) tree.push_back(p);
    for (const auto& p : all)
        if (p.pgid == group && std::none_of(tree.begin(), tree.end(), [&](const auto& t) { return t.pid == p.pid; }))
            tree.push_back(p);
    for (auto& p : tree) fillDetails(p);
    return tree;
}

std::string describeTree(pid_t root, bool stacks) {
    const std::vector<ProcessInfo> tree = processTree(root);
    // gdb gets 10 s a process and 30 s for the whole tree: the report must come, stacks or not.
    const auto budget = Clock::now() + std::chrono::seconds(30);
    if (tree.empty()) return "  (pid " + std::to_string(root) + " is gone)\n";
    std::map<pid_t, int> depth;
    std::ostringstream out;
    for (const auto& p : tree) {
        depth[p.pid] = depth.count(p.ppid) ? depth[p.ppid] + 1 : 0;
        char head[160];
        std::snprintf(head, sizeof head,
                      "  %*spid %d (ppid %d, group %d) %c%s%s, %.1f s old, %.2f s CPU; threads: ", 2 * depth[p.pid], "",
                      int(p.pid), int(p.ppid), int(p.pgid), p.state, p.wchan.empty() ? "" : " in ", p.wchan.c_str(),
                      p.ageS, p.cpuS);
        out << head << p.threads << "\n  " << std::string(std::size_t(2 * depth[p.pid]), ' ') << "  " << p.command
            << '\n';
        for (const std::string& kernel : kernelStacksOfBlockedThreads(p.pid)) out << kernel;
        if (stacks && p.state != 'Z' && p.state != 'D' && Clock::now() < budget) {  // gdb would wait on those
            std::istringstream lines(stacksOf(p.pid, std::min(budget, Clock::now() + std::chrono::seconds(10))));
            for (std::string line; std::getline(lines, line);) out << "      " << line << '\n';
        }
    }
    return out.str();
}

std::vector<ProcessInfo> killTree(pid_t root) {
    std::vector<ProcessInfo> tree = processTree(root);
    for (const auto& p : tree) kill(p.pid, SIGSTOP);
    // Children forked before the stop landed.
    for (const auto& p : processTree(root))
        if (std::none_of(tree.begin(), tree.end(), [&](const auto& t) { return t.pid == p.pid; })) {
            kill(p.pid, SIGSTOP);
            tree.push_back(p);
        }
    for (const auto& p : tree) kill(p.pid, SIGKILL);
    return tree;
}

double residentMb(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024;  // "VmRSS:   1234 kB"
    return 0;
}

int alive(const std::vector<ProcessInfo>& processes) {
    int n = 0;
    for (const auto& p : processes) {
        Stat s;
        if (readStat("/proc/" + std::to_string(p.pid) + "/stat", s) && s.start == p.start && s.state != 'Z' &&
            !(s.flags & kPfExiting))
            ++n;
    }
    return n;
}

std::optional<int> exitedStatus(pid_t pid) {
    Stat s;
    if (!readStat("/proc/" + std::to_string(pid) + "/stat", s) || !(s.flags & kPfExiting)) return std::nullopt;
    // Every thread on its way out: a leader whose main thread ended alone while others still run
    // has not exited.
    std::error_code ec;
    for (const auto& t : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
        Stat thread;
        if (readStat(t.path() / "stat", thread) && thread.state != 'Z' && !(thread.flags & kPfExiting))
            return std::nullopt;
    }
    return s.exitCode;
}

}  // namespace bop::test
