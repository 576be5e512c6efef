#include "process/ProcessTree.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <signal.h>
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
    unsigned long long utime = 0, stime = 0, start = 0;
};

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
    s.utime = std::stoull(f[11]);
    s.stime = std::stoull(f[12]);
    s.start = std::stoull(f[19]);
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

std::string stacksOf(pid_t pid) {
    static const bool haveGdb = std::system("command -v gdb >/dev/null 2>&1") == 0;
    if (!haveGdb) return "";
    const std::string cmd = "timeout -s KILL 20 gdb -p " + std::to_string(pid) +
                            " -batch -ex 'thread apply all bt 12' 2>/dev/null | grep -E '^(Thread|#)'";
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return "";
    std::string out;
    char buf[4096];
    while (const std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    pclose(p);
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
        if (stacks && p.state != 'Z' && p.state != 'D') {  // gdb would wait on those
            std::istringstream lines(stacksOf(p.pid));
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
        if (readStat("/proc/" + std::to_string(p.pid) + "/stat", s) && s.start == p.start && s.state != 'Z') ++n;
    }
    return n;
}

}  // namespace bop::test
