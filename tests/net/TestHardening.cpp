// bop-server against hostile input and its own blow-ups (issue: no input can stop or corrupt the
// server): every out-of-range number refused while the served torus keeps stepping, a probe
// dropped onto its particles at the strongest allowed setting, physics that goes unsound stopping
// with a checkpoint of the last sound state and nothing non-finite streamed, and periodic frames
// wrapped into the box.
#include "HapticLoopChecks.hpp"
#include "NetTestUtil.hpp"
#include "TestUtil.hpp"
#include "client/ClientSession.hpp"
#include "codec/MessageKind.hpp"
#include "codec/Ranges.hpp"
#include "protocol/HostileMessages.hpp"

#include <catch2/catch.hpp>
#include <zmq.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <thread>

using namespace bop;
using namespace bop::protocol;
using test::ChildProcess;
using namespace std::chrono_literals;

namespace {

bool finiteFrame(const StateFrame& f) {
    for (const float x : f.positions)
        if (!std::isfinite(x)) return false;
    return f.probeForce.allFinite() && std::isfinite(f.stats.kinetic) && std::isfinite(f.stats.potential);
}

// Sends `message` on a fresh session and returns the reason the server gave for refusing it.
std::string refusalOf(const std::string& endpoint, const Buffer& message) {
    zmq::context_t ctx(1);
    zmq::socket_t s(ctx, zmq::socket_type::dealer);
    s.set(zmq::sockopt::linger, 0);
    s.set(zmq::sockopt::rcvtimeo, 3000);
    s.connect(endpoint);
    s.send(zmq::buffer(encodeHello({})), zmq::send_flags::none);
    s.send(zmq::buffer(message), zmq::send_flags::none);
    for (zmq::message_t m; s.recv(m);) {
        const auto* p = static_cast<const std::uint8_t*>(m.data());
        const MessageKind kind = messageKind(p, m.size());
        if (kind == MessageKind::Refusal) return decodeRefusal(p, m.size()).value.reason;
        if (kind == MessageKind::CommandReply) return decodeCommandReply(p, m.size()).value.message;
    }
    return {};
}

// The small bulk box as a scene file, not periodic: a particle that leaves flies on. Without the
// step limit (max_step_r0 = 0) nothing holds a particle thrown hard.
std::string openBox(const test::TempDir& dir, bool limit = false) {
    return test::writeText(dir.file(limit ? "limited-box.toml" : "open-box.toml"),
                           std::string("[box]\nsize_r0 = [6.0, 6.0, 6.0]\nspacing_r0 = 1.0\nperiodic = false\n"
                                       "[[species]]\nname = \"bulk\"\nkind = \"volume\"\n[dynamics]\nmax_step_r0 = ") +
                               (limit ? "0.2\n" : "0.0\n"));
}

// The open box's start with particle 1 thrown at 1.1e6 length units per time: the drag slows it,
// and it passes 1e6 beyond the box after about 120 steps.
std::string thrownStart(const test::TempDir& dir, const std::string& scene) {
    const auto [code, out] = test::runCommand(test::buildDir() + "/dynamics_server/bop-server " + scene +
                                                  " --no-listen --steps 0 -o " + dir.file("start") + " 2>&1",
                                              60s);
    REQUIRE(code == 0);
    std::ifstream in(dir.file("start/checkpoint.xyz"));
    std::ostringstream edited;
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (n == 3) {  // particle 1: species, x y z, then vx
            std::istringstream fields(line);
            std::vector<std::string> f{std::istream_iterator<std::string>(fields), {}};
            f[4] = "1.1e6";
            line.clear();
            for (const auto& x : f) line += x + " ";
        }
        edited << line << "\n";
    }
    return test::writeText(dir.file("thrown.xyz"), edited.str());
}

// The step of a checkpoint file (its Step= key).
long long checkpointStep(const std::string& path) {
    std::ifstream in(path);
    std::string count, header;
    std::getline(in, count);
    std::getline(in, header);
    std::smatch m;
    return std::regex_search(header, m, std::regex("Step=([0-9]+)")) ? std::stoll(m[1]) : -1;
}

}  // namespace

TEST_CASE("the served torus keeps stepping through every out-of-range message and a probe dropped onto its particles",
          "[net][hardening]") {
    test::TempDir dir("hardening-served");
    ChildProcess srv(test::serverCommand(1, test::sourceDir() + "/config/scenes/torus.toml",
                                         {"--restart", test::builtTorus(), "-o", dir.file("run")}));
    ClientSession c;
    const SceneInfo scene = c.connect(srv.endpoint(), 20s);
    const std::vector<test::hostile::Case> cases = test::hostile::outOfRange(scene);
    for (const auto& k : cases) {
        INFO(k.what);
        CHECK(refusalOf(srv.endpoint(), k.message).find(k.field) != std::string::npos);
    }
    // The strongest probe a client may send, at the very position of a particle (as a frame
    // shows it): its force stays bounded and the bag stays sound.
    std::optional<StateFrame> f;
    for (int k = 0; k < 50 && !f; ++k) f = c.receiveFrame(200ms);
    REQUIRE(f);
    std::uint64_t seq = 0;
    for (const double k0 : {ranges::kMinProbeK0, 1.0, ranges::kMaxProbeK0})
        for (std::size_t i = 0; i < f->count(); i += f->count() / 7) {
            Probe p;
            p.active = true;
            p.position = Eigen::Vector3d(f->positions[3 * i], f->positions[3 * i + 1], f->positions[3 * i + 2]);
            p.k0 = k0;
            p.k1 = ranges::kMaxProbeK1;
            for (int t = 0; t < 40; ++t, std::this_thread::sleep_for(2ms)) p.seq = ++seq, c.sendProbe(p);
        }
    int frames = 0;
    for (const auto until = std::chrono::steady_clock::now() + 2s; std::chrono::steady_clock::now() < until;)
        if (const auto g = c.receiveFrame(200ms)) {
            ++frames;
            CHECK(finiteFrame(*g));
        }
    CHECK(frames > 5);
    INFO(srv.output());
    REQUIRE(srv.running());
    CHECK(srv.stop(SIGINT) == 0);
    const std::string out = srv.output();
    INFO(out);
    CHECK(out.find("final state:") != std::string::npos);
    CHECK(test::printedCount(out, "messages with values out of range refused") >= (long long)(cases.size()));
    CHECK(test::printedCount(out, "internal errors in the front") == 0);
}

TEST_CASE("a run whose physics goes unsound stops with exit 3 and the last sound state as its checkpoint",
          "[net][hardening][sound]") {
    test::TempDir dir("hardening-unsound");
    const std::string scene = openBox(dir);
    const std::string start = thrownStart(dir, scene);
    for (const int ranks : {1, 2}) {
        INFO(ranks << " ranks");
        const std::string out = dir.file("batch" + std::to_string(ranks));
        const std::string launch = ranks > 1 ? test::mpiexec() + " -np 2 --oversubscribe " : "";
        const auto [code, log] =
            test::runCommand(launch + test::buildDir() + "/dynamics_server/bop-server " + scene +
                                 " --no-listen --steps 400 --restart " + start + " -o " + out + " 2>&1",
                             120s);
        INFO(log);
        CHECK(code == 3);
        std::smatch m;
        REQUIRE(std::regex_search(
            log, m, std::regex("after step ([0-9]+) is not sound: .*particle 1 \\(species 1\\): more than 1e6")));
        const long long failed = std::stoll(m[1]);
        const long long saved = checkpointStep(out + "/checkpoint.xyz");
        CHECK(saved % 100 == 0);
        CHECK(saved < failed);
        CHECK(failed - saved <= 100);
        CHECK(saved > 0);  // not the start: a later sound state
        CHECK_FALSE(std::filesystem::exists(out + "/final.xyz"));
        // The checkpoint restarts: the run goes on from the last sound state.
        const auto again = test::runCommand(test::buildDir() + "/dynamics_server/bop-server " + scene +
                                                " --no-listen --steps 1 --restart " + out + "/checkpoint.xyz -o " +
                                                out + "/again 2>&1",
                                            60s);
        CHECK(again.first == 0);
    }
    // Served: frames up to the stop are finite, the server exits 3 by itself, nothing after it.
    ChildProcess srv(test::serverCommand(
        2, scene, {"--restart", start, "--wait-for-client", "--publish-hz", "200", "-o", dir.file("served")}));
    ClientSession c;
    c.connect(srv.endpoint(), 20s);
    int frames = 0;
    for (const auto until = std::chrono::steady_clock::now() + 10s;
         std::chrono::steady_clock::now() < until && srv.running();)
        if (const auto f = c.receiveFrame(100ms)) {
            ++frames;
            CHECK(finiteFrame(*f));
        }
    CHECK(frames > 0);
    const int code = srv.stop(SIGINT);
    // With the step limit (the default) the same throw is held to 0.2 r0 a step: the run stays sound.
    const std::string limited = openBox(dir, true);
    const auto held =
        test::runCommand(test::buildDir() + "/dynamics_server/bop-server " + limited +
                             " --no-listen --steps 400 --restart " + start + " -o " + dir.file("limited") + " 2>&1",
                         120s);
    INFO(held.second);
    CHECK(held.first == 0);
    const std::string log = srv.output();
    INFO(log);
    CHECK(log.find("is not sound") != std::string::npos);
    CHECK(log.find("the last sound state (step ") != std::string::npos);
    CHECK(code == 3);
    CHECK(checkpointStep(dir.file("served/checkpoint.xyz")) % 100 == 0);
    CHECK_FALSE(std::filesystem::exists(dir.file("served/final.xyz")));
}

TEST_CASE("frames of a periodic box carry positions inside it, float and quantised alike", "[net][hardening][wrap]") {
    test::TempDir dir("hardening-wrap");
    for (const bool quantised : {false, true}) {
        INFO((quantised ? "quantised" : "float") << " frames");
        std::vector<std::string> extra{"--publish-hz", "100", "-o", dir.file(quantised ? "q" : "f")};
        if (quantised) extra.push_back("--quantised");
        ChildProcess srv(test::serverCommand(2, test::sourceDir() + "/config/scenes/bulk-box.toml", extra));
        ClientSession c;
        const SceneInfo scene = c.connect(srv.endpoint(), 20s);
        long long frames = 0, outside = 0, onFace = 0, coordinates = 0;
        for (const auto until = std::chrono::steady_clock::now() + 3s; std::chrono::steady_clock::now() < until;) {
            const auto f = c.receiveFrame(200ms);
            if (!f) continue;
            ++frames;
            for (std::size_t i = 0; i < f->positions.size(); ++i) {
                const int a = int(i % 3);
                const double x = f->positions[i], lo = float(scene.boxLo[a]), hi = float(scene.boxHi[a]);
                outside += !(x >= lo && (quantised ? x <= hi : x < hi));
                const double step = (hi - lo) / 65535;  // a quantised position's resolution
                onFace += std::abs(x - lo) < 0.5 * step || std::abs(x - hi) < 0.5 * step;  // where clamping puts one
                ++coordinates;
            }
        }
        INFO(frames << " frames, " << outside << " coordinates outside, " << onFace << " on a face");
        CHECK(frames > 20);
        CHECK(outside == 0);
        // Quantised positions are clamped into the box, so the test is where they land: wrapped,
        // a coordinate falls within half a step of a face by chance, 3 N / 65535 = 0.09 a frame
        // here (6 in 302 frames); unwrapped and clamped, about one a frame more (measured without
        // the wrap: 302 in 301 quantised frames, and 140 coordinates outside the box in 301 float
        // frames).
        if (quantised) CHECK(double(onFace) <= 0.4 * double(frames));
        CHECK(coordinates > 0);
        srv.stop(SIGINT);
    }
}

TEST_CASE(
    "clients that come, misbehave and go leave the server's memory flat while a viewer and a haptic client keep "
    "working",
    "[net][hardening][churn]") {
    test::TempDir dir("hardening-churn");
    ChildProcess srv(
        test::serverCommand(1, test::sourceDir() + "/config/scenes/torus.toml",
                            {"--restart", test::builtTorus(), "--session-timeout", "1", "-o", dir.file("run")}));
    // The haptic client pokes the bag through the whole churn; the watcher in bop-churn is the viewer.
    ChildProcess haptic({test::buildDir() + "/haptic_client/bop-haptic", srv.endpoint(), "--device", "sim:poke",
                         "--seconds", "12", "--out", dir.file("haptic")},
                        30s, "bop-haptic: connected");
    const auto [code, churn] = test::runCommand(test::buildDir() + "/protocol/bop-churn " + srv.endpoint() +
                                                    " --clients 300 --concurrency 4 --burst 20 --baseline 2 --settle 3 "
                                                    "--server-pid " +
                                                    std::to_string(srv.pid()) + " 2>&1",
                                                120s);
    INFO(churn);
    REQUIRE(code == 0);
    const auto figure = [&](const std::string& key) {
        std::smatch m;
        REQUIRE(std::regex_search(churn, m, std::regex(key + "=([0-9.]+)")));
        return std::stod(m[1]);
    };
    CHECK(figure("clients") == 300);
    CHECK(figure("no_scene") == 0);  // every client's Hello answered, however it behaved
    CHECK(figure("refusals_received") >= 300);
    CHECK(figure("frames_during") > 10);  // the viewer kept taking frames
    std::printf(
        "churn: steps/s %.1f before, %.1f during, %.1f after; longest frame gap %.3f s (reported, not "
        "asserted: scripts/bench/churn.sh)\n",
        figure("steps_per_s_before"), figure("steps_per_s_during"), figure("steps_per_s_after"),
        figure("longest_frame_gap_s"));
    CHECK(figure("rss_after_mb") <= figure("rss_before_mb") + 4.0);
    CHECK(haptic.stop(SIGINT, 20s) == 0);
    const std::string felt = haptic.output();
    INFO(felt);
    std::smatch m;
    REQUIRE(std::regex_search(felt, m, std::regex("([0-9]+) feedback messages")));
    CHECK(std::stoll(m[1]) > 1000);  // feedback all along
    // The churn, the server and this loop share the machine's cores: the loop's rate is the
    // machine's (scripts/bench/churn.sh measures it quiet); that it never blocked on the server
    // and missed only the deadlines the machine took from it is the client's.
    test::checkHapticLoop(felt, dir.file("haptic") + "/haptic-trace.csv", 20);
    CHECK(srv.stop(SIGINT) == 0);
    const std::string out = srv.output();
    INFO(out);
    // The step loop never waited on the front for the churning clients.
    CHECK(test::longestFrontWaitMs(out) < 1000);
    CHECK(test::printedCount(out, "sessions expired") >= 300);
    CHECK(test::printedCount(out, "messages with values out of range refused") > 300);
    CHECK(test::printedCount(out, "malformed messages refused") > 300);
    CHECK(test::printedCount(out, "internal errors in the front") == 0);
}
