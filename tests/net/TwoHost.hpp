#pragma once
// Two hosts on this machine for the integration tests: scripts/two-host.sh makes the dynamics
// host and the graphics host (two network namespaces and a veth pair, with the impairments
// asked for) and removes them at the end. Where this machine cannot (no root, no namespaces, no
// netem for a delay), the test process prints the script's reason and exits 77, which ctest
// reports as skipped.
#include <string>
#include <vector>

namespace bop::test {

class TwoHost {
public:
    static constexpr const char* kServerAddress = "10.213.0.1";  // the dynamics host

    explicit TwoHost(const std::string& impairments);  // e.g. "--loss 10", "--delay 20", ""
    ~TwoHost();
    TwoHost(const TwoHost&) = delete;
    TwoHost& operator=(const TwoHost&) = delete;

    // argv run on the dynamics host ("dyn") or the graphics host ("gfx").
    std::vector<std::string> on(const std::string& host, std::vector<std::string> argv) const;
    // A shell command line run on that host.
    std::string shell(const std::string& host, const std::string& command) const;

private:
    std::string name_;
};

}  // namespace bop::test
