// bop-haptic tcp://HOST:PORT --device SPEC: the process holding the haptic device (docs/haptics.md).
// It downloads the gradient map, then runs the device loop at 1 kHz: read the device, step the
// local force model (virtual coupling to a proxy pushed by the server's newest reaction and by
// the map's field), send the proxy as the probe, render the force; traces as CSV.
#include "app/HapticRun.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/ParseVector.hpp"
#include "bop/common/ToolMain.hpp"
#include "codec/Ranges.hpp"

#include <CLI/CLI.hpp>

using namespace bop;

int main(int argc, char** argv) {
    return runTool("bop-haptic", [&] {
        CLI::App app{
            "bop-haptic: the haptic device loop (1 kHz): sends the probe to a served BoP run (bop-server) and "
            "renders the reaction force locally. Devices: sim:poke, sim:stroke, sim:circle, sim:finger, "
            "replay:FILE.mcap, spnav"};
        haptic::RunOptions o;
        std::string target, inward;
        app.add_option("endpoint", o.endpoint, "the server's control endpoint, tcp://HOST:PORT (not with --loop-only)");
        app.add_option("--device", o.device, "the device (default sim:poke)");
        app.add_flag("--loop-only", o.loopOnly, "run the device loop alone for --seconds and report its timing");
        app.add_option("--seconds", o.seconds, "stop after this long, s (0: when the device's script ends)")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--rate", o.rateHz, "loop rate, Hz")->check(CLI::Range(10.0, 10000.0));
        app.add_option("--out", o.outDir, "folder of haptic-trace.csv, stiffness.csv and stiffness.png");
        app.add_option("--target", target,
                       "scripted devices: the surface point x,y,z (length; default: the top of "
                       "the bag in the gradient map)");
        app.add_option("--inward", inward, "scripted devices: direction into the object (default 0,0,-1)");
        app.add_option("--depth", o.script.depth, "scripted devices: how far past the surface, length")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--standoff", o.script.standoff, "scripted devices: start this far outside, length")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--speed", o.script.speed, "scripted devices: length / s")->check(CLI::PositiveNumber);
        app.add_option("--hold", o.script.holdS, "scripted devices: seconds at depth")->check(CLI::NonNegativeNumber);
        app.add_option("--stroke-length", o.script.strokeLength, "sim:stroke: length")->check(CLI::PositiveNumber);
        app.add_option("--circle-radius", o.script.circleRadius, "sim:circle: length")->check(CLI::PositiveNumber);
        app.add_option("--turns", o.script.turns, "sim:circle: turns")->check(CLI::PositiveNumber);
        app.add_option("--stiffness", o.model.stiffness, "virtual coupling stiffness, force / length")
            ->check(CLI::PositiveNumber);
        app.add_option("--damping", o.model.damping, "virtual coupling damping, force * s / length")
            ->check(CLI::NonNegativeNumber);
        // The field acts on the 1 g proxy explicitly: stable below 4 m / dt^2 = 4,000 at 1 kHz.
        app.add_option("--field-stiffness", o.fieldStiffness,
                       "gradient-map field inside the bag, force / length "
                       "(0: off; at most 1000)")
            ->check(CLI::Range(0.0, 1000.0));
        app.add_option("--max-force", o.limits.maxForceN, "the device's largest force, N")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--newtons-per-force", o.newtonsPerForce,
                       "N on the device per simulation force unit, for a scene without materials (default 0.5); "
                       "a scene with [[material]] tables gives its forces in N")
            ->check(CLI::PositiveNumber);
        app.add_option("--force-scale", o.forceScale,
                       "the force on the device over the scene's (1: newtons as the tissue gives them; below 1 for "
                       "a device too weak for the tissue)")
            ->check(CLI::PositiveNumber);
        std::string workspaceCentre;
        app.add_option("--workspace-scale", o.workspaceScale,
                       "scene length per device mm (default: the device's "
                       "workspace spans the scene's box)")
            ->check(CLI::PositiveNumber);
        app.add_option("--workspace-centre", workspaceCentre,
                       "the scene point x,y,z at the workspace's centre "
                       "(default: the box's centre)");
        app.add_option("--max-stiffness", o.limits.maxStiffnessNPerMm,
                       "the stiffest spring the device renders stably, "
                       "N/mm")
            ->check(CLI::PositiveNumber);
        app.add_option("--k0", o.k0, "probe range scale (paper eq. 9; default: the server's)")
            ->check(CLI::Range(protocol::ranges::kMinProbeK0, protocol::ranges::kMaxProbeK0));
        app.add_option("--k1", o.k1, "probe strength (paper eq. 9; default: the server's)")
            ->check(CLI::Range(protocol::ranges::kMinProbeK1, protocol::ranges::kMaxProbeK1));
        app.add_flag("--cut", o.cut, "cut with the probe: the hand's path is a blade's (docs/haptics.md \"Cutting\")");
        app.add_option("--cut-button", o.cutButton, "cut while this device button is held (0, 1, ...)")
            ->check(CLI::Range(0, 31));
        app.add_option("--cut-radius", o.cutRadius, "the blade's radius, length (default: r0)")
            ->check(CLI::PositiveNumber);
        app.add_flag("--udp", o.udp, "probes and feedback as datagrams (the server's UDP port)");
        app.add_option("--reconnect-after", o.reconnectAfterS,
                       "no feedback for this long, s: connect to the server "
                       "again, every second until it answers (0: never)")
            ->check(CLI::NonNegativeNumber);
        app.add_option("--map-max-mb", o.mapMaxMb, "largest gradient map to download, MB")->check(CLI::PositiveNumber);
        app.add_option("--server-key", o.serverKeyFile,
                       "the server's CURVE public key file (bop-keys PREFIX.pub): encrypt "
                       "the session and accept only that server")
            ->check(CLI::ExistingFile);
        app.add_option("--client-key", o.clientKeyPrefix,
                       "this client's CURVE key pair PREFIX (.pub and .key), for a "
                       "server that lets in listed clients only");
        CLI11_PARSE(app, argc, argv);
        o.couplingGiven = app.count("--stiffness") > 0;
        o.fieldGiven = app.count("--field-stiffness") > 0;
        if (!target.empty()) o.target = parseVector3(target, "--target");
        if (!workspaceCentre.empty()) o.workspaceCentre = parseVector3(workspaceCentre, "--workspace-centre");
        if (!inward.empty()) o.script.inward = parseVector3(inward, "--inward");
        if (o.script.inward.norm() == 0) throw Error("--inward", "expected a direction, got 0,0,0");
        if (!o.loopOnly && o.endpoint.empty())
            throw Error("bop-haptic", "expected the server's endpoint (or --loop-only)");
        return o.loopOnly ? haptic::runLoopOnly(o) : haptic::runHaptic(o);
    });
}
