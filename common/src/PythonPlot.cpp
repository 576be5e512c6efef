#include "bop/common/PythonPlot.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace bop {
namespace {

// python, plots.py, KIND, FILES...
std::vector<std::string> command(const std::string& kind, const std::vector<std::string>& files) {
    const char* envPython = std::getenv("BOP_PYTHON");
    const char* envDir = std::getenv("BOP_PYTHON_DIR");
    std::string python = envPython && *envPython                   ? envPython
                         : ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3"
                                                                   : "python3";
    const std::string script = std::string(envDir && *envDir ? envDir : BOP_SOURCE_PYTHON_DIR) + "/bop/plots.py";
    std::vector<std::string> args{python, script, kind};
    args.insert(args.end(), files.begin(), files.end());
    return args;
}

std::vector<char*> pointers(std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    return argv;
}

}  // namespace

std::string plotWithMatplotlib(const std::string& kind, const std::vector<std::string>& files) {
    std::vector<std::string> args = command(kind, files);
    const std::string python = args[0], script = args[1];
    std::vector<char*> argv = pointers(args);
    const pid_t pid = ::fork();
    if (pid < 0) return "cannot start " + python + ": " + std::strerror(errno);
    if (pid == 0) {
        // Only async-signal-safe calls between fork and exec: the tool has other threads, whose
        // locks (stdio's, malloc's) the child may have inherited held.
        // plots.py names the file it wrote on stdout; the tool says that itself.
        const int null = ::open("/dev/null", O_WRONLY);
        if (null >= 0) ::dup2(null, 1);
        ::execvp(argv[0], argv.data());
        ::_exit(127);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return "waiting for " + python + ": " + std::strerror(errno);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return python + " is not installed";
    return script + " " + kind + " failed (exit " +
           std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) +
           "; it needs python3-matplotlib and python3-numpy)";
}

std::string plotWithMatplotlibDetached(const std::string& kind, const std::vector<std::string>& files) {
    std::vector<std::string> args = command(kind, files);
    std::string said;
    for (const auto& a : args) said += (said.empty() ? "" : " ") + a;
    std::vector<char*> argv = pointers(args);
    const pid_t pid = ::fork();  // the child as in plotWithMatplotlib: async-signal-safe calls only
    if (pid < 0) return said;
    if (pid == 0) {
        // A session of its own, outside the rank's process group; the middle process leaves at
        // once, so the plotter is nobody's child to wait for.
        ::setsid();
        if (::fork() != 0) ::_exit(0);
        const int null = ::open("/dev/null", O_RDWR);
        for (int fd = 0; fd < 3; ++fd) ::dup2(null, fd);
        for (int fd = 3; fd < 1024; ++fd) ::close(fd);  // MPI's and the front's sockets stay with the rank
        ::execvp(argv[0], argv.data());
        ::_exit(127);
    }
    while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
    return said;
}

}  // namespace bop
