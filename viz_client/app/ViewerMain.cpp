// bop-viewer tcp://HOST:PORT: watches, builds and drives a served run (docs/viewer.md). A GLFW
// window with the Dear ImGui panel, or --headless: the same drawing through EGL into PNG files.
#include "app/ViewerLoops.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/ParseVector.hpp"
#include "bop/common/ToolMain.hpp"
#include "codec/Ranges.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>

using namespace bop;

int main(int argc, char** argv) {
    return runTool("bop-viewer", [&] {
        CLI::App app{
            "bop-viewer: watches, builds and drives a served BoP run (bop-server). A window with a panel "
            "(GLFW, Dear ImGui), or --headless: frames drawn through EGL and written as PNG files"};
        std::string endpoint, probeFrom, probeTo;
        viz::LoopOptions o;
        o.outDir = "out/viewer";
        bool headless = false, noPanel = false;
        double wantedHz = 0, connectS = 0, probeSeconds = 2;
        app.add_option("endpoint", endpoint, "the server's control endpoint, tcp://HOST:PORT")->required();
        app.add_flag("--headless", headless, "no window: draw through EGL into PNG files (--out)");
        app.add_option("--frames", o.frames,
                       "new frames to draw, then exit (headless default 10; window: 0 = until closed)")
            ->check(CLI::Range(0, 1000000));
        app.add_option("--out", o.outDir, "folder of the headless pictures, frames.csv and the window's screenshots");
        app.add_option("--screenshot", o.screenshot, "also write the last picture to this PNG file");
        app.add_option("--width", o.width, "picture or window width, pixels")->check(CLI::Range(16, 8192));
        app.add_option("--height", o.height, "picture or window height, pixels")->check(CLI::Range(16, 8192));
        app.add_flag("--no-panel", noPanel, "draw the scene only");
        app.add_option("--fps", wantedHz, "frames per second wanted from the server (0: all it publishes)")
            ->check(CLI::Range(0.0, 1000.0));
        app.add_option("--connect-timeout", connectS,
                       "give up when not connected for this long, s (0 = never; "
                       "headless default 30)")
            ->check(CLI::NonNegativeNumber);
        double lostAfterS = 10;
        app.add_option("--lost-after", lostAfterS,
                       "no frame for this long: the server is taken as lost and connected "
                       "to again, s")
            ->check(CLI::Range(1.0, 3600.0));
        app.add_option("--probe-from", probeFrom, "headless: a scripted probe starts here, x,y,z (length)");
        app.add_option("--probe-to", probeTo, "headless: ... and moves here (length)");
        app.add_option("--probe-seconds", probeSeconds, "headless: ... over this long from the first frame, s")
            ->check(CLI::PositiveNumber);
        double probeK0 = 0, probeK1 = 0, cutRadius = 0;
        app.add_option("--probe-cut", cutRadius,
                       "headless: the scripted probe is a blade of this radius (length): its path cuts the bags")
            ->check(CLI::PositiveNumber);
        app.add_option("--probe-k0", probeK0,
                       "headless: the probe's range scale k0 (paper eq. 9; default: the server's)")
            ->check(CLI::Range(protocol::ranges::kMinProbeK0, protocol::ranges::kMaxProbeK0));
        app.add_option("--probe-k1", probeK1, "headless: the probe's strength k1 (paper eq. 9; default: the server's)")
            ->check(CLI::Range(protocol::ranges::kMinProbeK1, protocol::ranges::kMaxProbeK1));
        app.add_option("--hide", o.hide,
                       "a bag (or species) to hide, by its name in the scene (repeat for several; the panel's "
                       "bag list shows and hides them too)");
        int udpPort = 0;
        app.add_option("--udp-port", udpPort,
                       "frames as datagrams to this local UDP port (the server's datagram mode: "
                       "a frame with a datagram lost is dropped and counted; 0: frames over TCP)")
            ->check(CLI::Range(0, 65535));
        std::string serverKey, clientKey;
        app.add_option("--server-key", serverKey,
                       "the server's CURVE public key file (bop-keys PREFIX.pub): encrypt the "
                       "session and accept only that server")
            ->check(CLI::ExistingFile);
        app.add_option("--client-key", clientKey,
                       "this client's CURVE key pair PREFIX (.pub and .key), for a server "
                       "that lets in listed clients only");
        CLI11_PARSE(app, argc, argv);
        o.panel = !noPanel;
        if (probeFrom.empty() != probeTo.empty()) throw Error("--probe-from/--probe-to", "expected both or neither");
        if (!probeFrom.empty()) {
            if (!headless)
                throw Error("--probe-from", "a scripted probe is for --headless runs; the window has the mouse");
            o.probe = viz::ProbeScript{parseVector3(probeFrom, "--probe-from"),
                                       parseVector3(probeTo, "--probe-to"),
                                       probeSeconds,
                                       probeK0,
                                       probeK1,
                                       cutRadius};
        }
        if (headless && o.frames == 0) o.frames = 10;
        if (headless && connectS == 0) connectS = 30;
        protocol::ClientOptions client;
        client.clientName = "bop-viewer";
        client.frameRateHz = float(wantedHz);
        client.udpFramePort = std::uint16_t(udpPort);
        protocol::useCurveKeys(client, serverKey, clientKey);
        viz::LinkOptions link;
        link.giveUpAfter = std::chrono::milliseconds(long(1000 * connectS));
        link.lostAfter = std::chrono::seconds(long(lostAfterS + 0.5));
        viz::ViewerLink session(endpoint, client, link);
        return headless ? viz::runHeadless(session, o) : viz::runWindow(session, o);
    });
}
