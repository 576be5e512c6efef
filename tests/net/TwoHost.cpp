#include "TwoHost.hpp"

#include "NetTestUtil.hpp"
#include "TestUtil.hpp"

#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include <unistd.h>

namespace bop::test {
namespace {

using namespace std::chrono_literals;

std::string script() {
    return sourceDir() + "/scripts/two-host.sh";
}
}  // namespace

TwoHost::TwoHost(const std::string& impairments) : name_("bth" + std::to_string(getpid())) {
    setenv("BOP_BUILD_DIR", buildDir().c_str(), 1);  // where the script finds bop-netdelay
    const auto [check, why] = runCommand(script() + " check " + impairments + " 2>&1", 30s);
    if (check == 77) {  // not possible here: the whole test is skipped, saying why
        std::printf("%s", why.c_str());
        std::fflush(stdout);
        std::exit(77);
    }
    if (check != 0) throw std::runtime_error("two-host.sh check " + impairments + " failed:\n" + why);
    // Hosts left by a test process that was killed (a ctest timeout) go first.
    runCommand(
        "for ns in $(ip netns list 2>/dev/null | grep -oE '^bth[0-9]+-(dyn|gfx)'); do p=${ns#bth}; "
        "kill -0 ${p%-*} 2>/dev/null || ip netns del $ns; done",
        30s);
    const auto [code, out] = runCommand(script() + " up " + name_ + " " + impairments + " 2>&1", 60s);
    if (code != 0) {
        runCommand(script() + " down " + name_, 30s);  // the destructor does not run after a throw
        throw std::runtime_error("two-host.sh up failed:\n" + out);
    }
    std::printf("%s", out.c_str());
}

TwoHost::~TwoHost() {
    try {
        runCommand(script() + " down " + name_, 30s);
    } catch (const std::exception& e) {  // reported; a destructor may run while a test fails
        std::fprintf(stderr, "two-host.sh down %s: %s\n", name_.c_str(), e.what());
    }
}

std::vector<std::string> TwoHost::on(const std::string& host, std::vector<std::string> argv) const {
    argv.insert(argv.begin(), {"ip", "netns", "exec", name_ + "-" + host});
    return argv;
}

std::string TwoHost::shell(const std::string& host, const std::string& command) const {
    return "ip netns exec " + name_ + "-" + host + " " + command;
}

}  // namespace bop::test
