#pragma once
// The processes a test started, as /proc shows them: a child, its descendants (mpirun's ranks
// sit in process groups of their own, so a group alone misses them) and its group's members.
// For the report a test prints when a child misses its deadline, and for killing all of them.
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

namespace bop::test {

struct ProcessInfo {
    pid_t pid = 0, ppid = 0, pgid = 0;
    char state = '?';              // R running, S sleeping, D disk, T stopped, Z zombie (proc(5))
    std::string wchan;             // the kernel function it sleeps in ("do_sys_poll", "futex_wait_queue", ...)
    double ageS = 0, cpuS = 0;     // since it started; user + system time, seconds
    std::string threads;           // its threads' states and wait channels, counted ("S futex_wait_queue x3, R")
    std::string command;           // its command line, cut at 160 characters
    unsigned long long start = 0;  // its start time in clock ticks since boot: (pid, start) names it even after reuse
};

// `root` and every process descending from it or in its process group, parents before children.
std::vector<ProcessInfo> processTree(pid_t root);

// The tree as lines: indented by depth, each with pid, state, wait channel, age, CPU time,
// threads and command. With `stacks` and gdb on the PATH, each process's threads' first frames.
std::string describeTree(pid_t root, bool stacks);

// Stops every process of the tree (SIGSTOP, so none forks or is re-parented meanwhile), then
// kills each (SIGKILL). Returns them, for waitGone().
std::vector<ProcessInfo> killTree(pid_t root);

// Its resident memory (VmRSS), MB; 0 once it is gone.
double residentMb(pid_t pid);

// How many of `processes` still run (zombies and processes that called exit do not count; a
// reused pid is another process).
int alive(const std::vector<ProcessInfo>& processes);

// Once `pid` called exit and until it is reaped: its status, as waitpid will give it. The kernel
// can hold an exiting process for minutes (tearing down its memory while a page-reclaim thread
// holds the lock of a file it mapped: docs/faults.md); what it did is done by then.
std::optional<int> exitedStatus(pid_t pid);

}  // namespace bop::test
