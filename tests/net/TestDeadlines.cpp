// The tests' own deadlines (process/ChildProcess.hpp): a client waiting on a server that never
// answers makes its test fail within the deadline it was given, saying what it waited for, with
// the process tree, each process's state and the last lines of every child, its whole tree killed.
// Without them such a test waits for ctest's timeout and leaves nothing to read.
#include "NetTestUtil.hpp"

#include <catch2/catch.hpp>

#include <csignal>

using namespace bop;
using namespace std::chrono_literals;

namespace {

// A TCP server that accepts connections and never says a word.
const char* kSilentServer = R"py(
import socket, time
s = socket.socket()
s.bind(("127.0.0.1", 0))
s.listen()
print("listening on tcp://127.0.0.1:%d (a server that never answers)" % s.getsockname()[1], flush=True)
peers = []
while True:
    c, _ = s.accept()
    peers.append(c)
)py";

bool gone(int pid) {
    return kill(pid, 0) != 0;
}

}  // namespace

TEST_CASE("a client waiting on a server that never answers fails its test within the deadline, saying where it was",
          "[net][deadline]") {
    test::ChildProcess silent({"python3", "-c", kSilentServer});
    // bop-haptic waits up to 30 s for the server's scene; the test gives it 3 s.
    test::ChildProcess client({test::buildDir() + "/haptic_client/bop-haptic", silent.endpoint(), "--device",
                               "sim:poke", "--out", test::outputDir("deadline", "haptic")},
                              {}, "");
    const auto t0 = std::chrono::steady_clock::now();
    std::string report;
    try {
        client.wait(3s);
        FAIL("the client ended although the server never answered:\n" << client.output());
    } catch (const test::DeadlineMissed& e) {
        report = e.report;
        INFO(e.what());
        CHECK(std::string(e.what()).find("did not end within 3.0 s") != std::string::npos);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(report);
    CHECK(seconds < 3 + 10);  // the report and the kill take seconds at most, not ctest's 300
    CHECK(report.find("DEADLINE: pid " + std::to_string(client.pid()) + " did not end") != std::string::npos);
    CHECK(report.find("its process tree:") != std::string::npos);
    CHECK(report.find("bop-haptic " + silent.endpoint()) != std::string::npos);  // its command line
    CHECK(report.find("threads: ") != std::string::npos);                        // each process's threads' states
    CHECK(report.find("its last lines of output:") != std::string::npos);
    // The other child of the test, with its own last line.
    CHECK(report.find("another child still running, pid " + std::to_string(silent.pid())) != std::string::npos);
    CHECK(report.find("a server that never answers") != std::string::npos);
    CHECK(gone(client.pid()));
    CHECK(silent.running());  // only the child that missed its deadline was killed
    CHECK(silent.stop(SIGTERM, 10s) == 128 + SIGTERM);
}

TEST_CASE("a child that never prints what a test waits for fails it within the deadline", "[net][deadline]") {
    const auto t0 = std::chrono::steady_clock::now();
    int pid = 0;
    try {
        test::ChildProcess child({"sh", "-c", "echo a line before the silence; exec sleep 1000"}, 2s, "listening on ");
        FAIL("it printed what it never prints");
    } catch (const test::DeadlineMissed& e) {
        INFO(e.report);
        CHECK(std::string(e.what()).find("did not print 'listening on ' within 2.0 s") != std::string::npos);
        CHECK(e.report.find("a line before the silence") != std::string::npos);
        CHECK(e.report.find("sleep 1000") != std::string::npos);  // the process tree names it
        const auto at = e.report.find("DEADLINE: pid ");
        REQUIRE(at != std::string::npos);
        pid = std::stoi(e.report.substr(at + 14));
    }
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 2 + 10);
    REQUIRE(pid > 0);
    CHECK(gone(pid));
}
