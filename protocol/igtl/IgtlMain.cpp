// bop-igtl: a served run's bag, probe and label map for OpenIGTLink clients (3D Slicer's
// OpenIGTLinkIF, PLUS, MITK, CustusX), and a tracked tool's TRANSFORM as BoP's probe
// (IgtlBridge.hpp; docs/igtl.md). Runs until interrupted (Ctrl-C) or --seconds have passed.
#include "IgtlBridge.hpp"
#include "bop/common/ToolMain.hpp"
#include "codec/Ranges.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <csignal>
#include <cstdio>

namespace {
std::atomic<bool> gStop{false};
void onSignal(int) {
    gStop = true;
}
}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-igtl", [&] {
        bop::igtl::BridgeOptions o;
        double timeoutS = 10;
        CLI::App app{
            "bop-igtl: an OpenIGTLink server (3D Slicer, PLUS) for a served BoP run: the bag's surface and volume "
            "particles as POLYDATA, the probe as TRANSFORM 'Probe' and its reaction as POLYDATA 'ProbeForce', the "
            "scene's label map as IMAGE 'BoP labels' once per connection, all in the scene's model space in mm; a "
            "TRANSFORM named --tool moves BoP's probe to its translation"};
        app.add_option("endpoint", o.endpoint, "the served run, tcp://HOST:PORT (bop-server prints it)")->required();
        app.add_option("--igtl-port", o.igtl.port, "TCP port OpenIGTLink clients connect to (0: any free one)")
            ->default_val(18944)
            ->check(CLI::Range(0, 65535));
        app.add_option("--igtl-bind", o.igtl.bind, "IPv4 address to listen on; '*' for every interface")
            ->default_val("127.0.0.1");
        app.add_option("--rate", o.rateHz, "bag updates sent per second, Hz")
            ->default_val(30)
            ->check(CLI::Range(0.5, 1000.0));
        app.add_option("--tool", o.tool,
                       "device name of the TRANSFORM that moves the probe (PLUS: StylusTipToReference)")
            ->default_val("StylusTipToReference");
        app.add_option("--force-scale", o.forceMmPerN, "length of the ProbeForce line per newton of reaction, mm/N")
            ->default_val(10)
            ->check(CLI::Range(0.0, 1e6));
        app.add_option("--k0", o.k0, "the probe's range scale (paper eq. 9), dimensionless")
            ->default_val(1.0)
            ->check(CLI::Range(bop::protocol::ranges::kMinProbeK0, bop::protocol::ranges::kMaxProbeK0));
        app.add_option("--k1", o.k1, "the probe's strength (paper eq. 9), dimensionless")
            ->default_val(1.0)
            ->check(CLI::Range(bop::protocol::ranges::kMinProbeK1, bop::protocol::ranges::kMaxProbeK1));
        app.add_option("--timeout", timeoutS, "connecting to the run and downloading its map, s")
            ->default_val(10)
            ->check(CLI::Range(0.1, 3600.0));
        app.add_option("--seconds", o.seconds, "stop after this long, s (0: run until interrupted)")
            ->default_val(0)
            ->check(CLI::Range(0.0, 1e9));
        CLI11_PARSE(app, argc, argv);
        if (o.tool.empty() || o.tool.size() > bop::igtl::kDeviceSize)
            throw bop::Error("bop-igtl", "--tool must be 1 to 20 characters, not '" + o.tool + "'");
        o.timeout = std::chrono::milliseconds(std::llround(timeoutS * 1000));
        std::signal(SIGINT, onSignal);
        std::signal(SIGTERM, onSignal);
        const auto log = [](const std::string& line) {
            std::printf("bop-igtl: %s\n", line.c_str());
            std::fflush(stdout);
        };
        const bop::igtl::BridgeStats s = bop::igtl::runBridge(o, gStop, log, [](int port) {
            std::printf("OpenIGTLink listening on port %d\n", port);
            std::fflush(stdout);
        });
        std::printf(
            "bop-igtl: %llu frames sent as updates, %llu probes from '%s'; OpenIGTLink: %zu connections, "
            "%llu messages sent, %llu replaced unsent, %zu received, %zu skipped, %zu closed for bad headers\n",
            (unsigned long long)s.frames, (unsigned long long)s.probes, o.tool.c_str(), s.igtl.accepted,
            (unsigned long long)s.igtl.sent, (unsigned long long)s.igtl.replaced, s.igtl.received, s.igtl.skipped,
            s.igtl.closed);
        return 0;
    });
}
