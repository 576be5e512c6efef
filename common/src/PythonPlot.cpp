#include "bop/common/PythonPlot.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include <sys/wait.h>
#include <unistd.h>

namespace bop {

std::string plotWithMatplotlib(const std::string& kind, const std::vector<std::string>& files) {
    const char* envPython = std::getenv("BOP_PYTHON");
    const char* envDir = std::getenv("BOP_PYTHON_DIR");
    std::string python = envPython && *envPython                   ? envPython
                         : ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3"
                                                                   : "python3";
    const std::string script = std::string(envDir && *envDir ? envDir : BOP_SOURCE_PYTHON_DIR) + "/bop/plots.py";
    std::vector<std::string> args{python, script, kind};
    args.insert(args.end(), files.begin(), files.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) return std::string("cannot start ") + python + ": " + std::strerror(errno);
    if (pid == 0) {
        // plots.py names the file it wrote on stdout; the tool says that itself.
        if (FILE* null = std::freopen("/dev/null", "w", stdout)) (void)null;
        ::execvp(argv[0], argv.data());
        std::fprintf(stderr, "cannot run %s: %s\n", argv[0], std::strerror(errno));
        ::_exit(127);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return std::string("waiting for ") + python + ": " + std::strerror(errno);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
    if (WIFEXITED(status) && WEXITSTATUS(status) == 127) return python + " is not installed";
    return script + " " + kind + " failed (exit " +
           std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) +
           "; it needs python3-matplotlib and python3-numpy)";
}

}  // namespace bop
