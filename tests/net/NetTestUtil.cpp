#include "NetTestUtil.hpp"

#include "TestUtil.hpp"

#include <filesystem>
#include <regex>
#include <stdexcept>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace bop::test {

std::string buildDir() {
    return BOP_BUILD_DIR;
}

namespace {

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

}  // namespace

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

double longestFrontWaitMs(const std::string& output) {
    std::smatch m;
    if (!std::regex_search(output, m,
                           std::regex("the step loop waited on the front [0-9]+ times, longest ([0-9.e+-]+) ms")))
        throw std::runtime_error("the server printed no wait on the front; its output:\n" + output);
    return std::stod(m[1]);
}

double serverResidentMb(int pid) {
    double mb = 0;
    for (const ProcessInfo& p : processTree(pid_t(pid)))
        if (p.command.find("bop-server") != std::string::npos && p.command.find("mpiexec") == std::string::npos &&
            p.command.find("ip netns") == std::string::npos)
            mb += residentMb(p.pid);
    return mb;
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
                                                "/config/scenes/torus.toml --no-listen -o " + made.string() + " 2>&1",
                                            std::chrono::minutes(5));
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
