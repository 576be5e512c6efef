#include "ServerProcess.hpp"

#include "TestUtil.hpp"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

namespace bop::test {

std::string buildDir() {
    return BOP_BUILD_DIR;
}

namespace {
// Processes of group `pgid` still running (zombies left to their new parent do not count): the
// ranks mpirun started live on for a moment after it exits, holding their ports.
int groupMembersAlive(pid_t pgid) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator("/proc")) {
        std::ifstream stat(e.path() / "stat");
        std::string text;
        if (!std::getline(stat, text)) continue;
        const auto close = text.rfind(')');
        if (close == std::string::npos) continue;
        std::istringstream rest(text.substr(close + 1));
        char state = 0;
        long ppid = 0, pgrp = 0;
        if (rest >> state >> ppid >> pgrp && pgrp == pgid && state != 'Z') ++n;
    }
    return n;
}

bool portFree(int type, int port) {
    const int fd = socket(AF_INET, type, 0);
    if (fd < 0) return false;
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);  // as ZeroMQ binds
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(std::uint16_t(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    const bool ok = bind(fd, reinterpret_cast<const sockaddr*>(&a), sizeof a) == 0;
    close(fd);
    return ok;
}

// Open MPI refuses root unless told (CI runs as root) and more ranks than cores unless told.
void allowMpiAsRoot() {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
}
}  // namespace

std::pair<int, std::string> runCommand(const std::string& command) {
    allowMpiAsRoot();
    FILE* p = popen(command.c_str(), "r");
    if (!p) throw std::runtime_error("cannot run " + command);
    std::string out;
    char buf[4096];
    while (const std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    const int status = pclose(p);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}
std::string mpiexec() {
    return BOP_MPIEXEC;
}

std::vector<std::string> serverCommand(int ranks, const std::string& scenePath, const std::vector<std::string>& extra) {
    std::vector<std::string> a;
    if (ranks > 1) a = {mpiexec(), "-np", std::to_string(ranks), "--oversubscribe"};
    a.insert(a.end(), {buildDir() + "/dynamics_server/bop-server", scenePath, "--port", "0"});
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

long long printedCount(const std::string& output, const std::string& what) {
    std::smatch m;
    return std::regex_search(output, m, std::regex("([0-9]+) " + what)) ? std::stoll(m[1]) : -1;
}

ServerProcess::ServerProcess(std::vector<std::string> argv, std::chrono::milliseconds timeout,
                             const std::string& ready) {
    allowMpiAsRoot();
    int pipeFds[2];
    if (pipe(pipeFds) != 0) throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error(std::string("fork: ") + std::strerror(errno));
    if (pid_ == 0) {
        dup2(pipeFds[1], 1);
        dup2(pipeFds[1], 2);
        close(pipeFds[0]);
        close(pipeFds[1]);
        setpgid(0, 0);  // its own group: stop() reaches mpirun's ranks too
        std::vector<char*> args;
        for (auto& a : argv) args.push_back(a.data());
        args.push_back(nullptr);
        execvp(args[0], args.data());
        _exit(127);
    }
    close(pipeFds[1]);
    fd_ = pipeFds[0];
    fcntl(fd_, F_SETFL, O_NONBLOCK);
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
        drain(50);
        if (ready != "listening on " && out_.find(ready) != std::string::npos) return;
        const auto at = out_.find("listening on ");
        if (ready == "listening on " && at != std::string::npos) {
            const auto end = out_.find_first_of(" \n", at + 13);
            if (end != std::string::npos) {
                endpoint_ = out_.substr(at + 13, end - at - 13);
                return;
            }
        }
        if (!running()) break;
    }
    kill(-pid_, SIGKILL);
    throw std::runtime_error(argv[0] + " did not print '" + ready + "'; its output:\n" + out_);
}

ServerProcess::~ServerProcess() {
    if (running()) {
        kill(-pid_, SIGKILL);
        waitpid(pid_, &status_, 0);
    }
    if (fd_ >= 0) close(fd_);
}

void ServerProcess::drain(int waitMs) {
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, waitMs) <= 0) return;
    char buf[4096];
    for (;;) {
        const ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) break;
        out_.append(buf, std::size_t(n));
    }
}

bool ServerProcess::running() {
    if (status_ != -1) return false;
    int st = 0;
    const pid_t r = waitpid(pid_, &st, WNOHANG);
    if (r == pid_) {
        status_ = st;
        return false;
    }
    return true;
}

int ServerProcess::stop(int signal, std::chrono::milliseconds timeout) {
    if (running()) kill(-pid_, signal);
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (running() && std::chrono::steady_clock::now() < until) drain(20);
    // mpirun may exit before its ranks: their ports are free only once they are gone too.
    while (groupMembersAlive(pid_) > 0 && std::chrono::steady_clock::now() < until) drain(20);
    drain(0);
    if (running() || groupMembersAlive(pid_) > 0) {
        kill(-pid_, SIGKILL);
        if (running()) waitpid(pid_, &status_, 0);
        return -1;
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
}

int freeBasePort() {
    // Below the kernel's ephemeral range (32768 and up), where no connection or port-0 bind of
    // another test lands; a start that differs by process spreads parallel tests apart.
    const int lo = 20000, span = 12000;
    for (int k = 0; k < span; k += 3) {
        const int p = lo + (int(getpid()) * 7 + k) % (span - 3);
        if (portFree(SOCK_STREAM, p) && portFree(SOCK_STREAM, p + 1) && portFree(SOCK_STREAM, p + 2) &&
            portFree(SOCK_DGRAM, p + 2))
            return p;
    }
    throw std::runtime_error("no three free ports in a row between 20000 and 32000 on 127.0.0.1");
}

std::string ServerProcess::output() {
    drain(0);
    return out_;
}

const std::string& builtTorus() {
    namespace fs = std::filesystem;
    static const std::string xyz = [] {
        const fs::path dir = fs::path(buildDir()) / "test-output" / "built-torus", file = dir / "final.xyz";
        // Made again when the server, the scene or its mesh is newer than the bag made with them.
        bool fresh = fs::exists(file);
        for (const fs::path& input : {fs::path(buildDir()) / "dynamics_server" / "bop-server",
                                      fs::path(sourceDir()) / "config" / "scenes" / "torus.toml",
                                      fs::path(sourceDir()) / "config" / "models" / "torus.obj"})
            fresh = fresh && fs::last_write_time(file) > fs::last_write_time(input);
        if (fresh) return file.string();
        const fs::path made = dir.string() + ".tmp-" + std::to_string(getpid());  // whole, or not there
        fs::remove_all(made);
        const auto [code, out] = runCommand(buildDir() + "/dynamics_server/bop-server " + sourceDir() +
                                            "/config/scenes/torus.toml --no-listen -o " + made.string() + " 2>&1");
        if (code != 0) throw std::runtime_error("the torus batch run failed:\n" + out);
        fs::remove_all(dir);
        fs::rename(made, dir);
        return file.string();
    }();
    return xyz;
}

std::string outputDir(const std::string& group, const std::string& name) {
    const std::filesystem::path d = std::filesystem::path(buildDir()) / "test-output" / group / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d.string();
}

}  // namespace bop::test
