// bop-deadline: runs a command with a deadline, for the tests that are scripts or mpirun lines
// (ctest's mpi and cli entries). Past the deadline it prints what ChildProcess prints (the
// process tree with states, wait channels and stacks, the command's last lines), kills the whole
// tree and exits 124, in seconds rather than at ctest's timeout.
#include "process/ChildProcess.hpp"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <signal.h>

namespace {

volatile std::sig_atomic_t gChild = 0;

// A signal sent to bop-deadline goes on to the command's process group (a script's `kill -TERM`
// reaches mpirun as it would without bop-deadline in between).
void passOn(int signal) {
    if (gChild > 0) kill(-pid_t(gChild), signal);
}

int usage(const char* why) {
    if (why) std::fprintf(stderr, "bop-deadline: %s\n", why);
    std::fprintf(why ? stderr : stdout,
                 "usage: bop-deadline [--log FILE] SECONDS -- COMMAND [ARGUMENTS...]\n"
                 "  runs COMMAND in a process group of its own, its output (stdout and stderr) passed on as it\n"
                 "  comes (to FILE with --log); exits with its exit code (128 + signal if killed). When it has\n"
                 "  not ended after SECONDS: prints its process tree (states, wait channels, stacks where gdb is\n"
                 "  installed) and its last lines on stderr, kills every process of the tree and exits 124.\n"
                 "  SIGINT, SIGTERM, SIGHUP, SIGUSR1 and SIGUSR2 are passed on to COMMAND's process group.\n");
    return why ? 2 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    if (!args.empty() && (args[0] == "-h" || args[0] == "--help")) return usage(nullptr);
    std::string log;
    if (args.size() >= 2 && args[0] == "--log") {
        log = args[1];
        args.erase(args.begin(), args.begin() + 2);
    }
    if (args.size() < 3 || args[1] != "--") return usage("expected SECONDS -- COMMAND");
    char* end = nullptr;
    const double seconds = std::strtod(args[0].c_str(), &end);
    if (*end != '\0' || !(seconds > 0))
        return usage(("SECONDS: expected a positive number, got '" + args[0] + "'").c_str());
    std::FILE* to = stdout;
    if (!log.empty() && !(to = std::fopen(log.c_str(), "w"))) {
        std::fprintf(stderr, "bop-deadline: cannot write %s: %s\n", log.c_str(), std::strerror(errno));
        return 2;
    }
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each line out as it comes
    try {
        bop::test::ChildProcess child({args.begin() + 2, args.end()}, {}, "");
        child.echoTo(to);
        gChild = child.pid();
        struct sigaction a {};
        a.sa_handler = passOn;
        a.sa_flags = SA_RESTART;
        for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGUSR1, SIGUSR2}) sigaction(signal, &a, nullptr);
        return child.wait(bop::test::Milliseconds(static_cast<long long>(seconds * 1000)));
    } catch (const bop::test::DeadlineMissed& e) {
        std::fprintf(stderr, "bop-deadline: %s\n", e.what());
        return 124;
    }
}
