// bop-viewer against served runs (2 ranks): headless pictures of a running server, a scripted
// probe pressed into the torus bag (the frames show it; the server's state and the reaction
// force say it indented the surface), and the window under Xvfb with its panel. Pictures stay
// in build/test-output/viewer/ to look at.
#include "NetTestUtil.hpp"
#include "TestUtil.hpp"
#include "client/ClientSession.hpp"

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <stb/stb_image.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <thread>

using namespace bop;
using namespace std::chrono_literals;

namespace {

std::vector<std::string> server(const std::string& scene, std::vector<std::string> extra) {
    return test::serverCommand(2, test::sourceDir() + "/config/scenes/" + scene + ".toml", extra);
}

// The last `n` lines of `text` (all of it if it has fewer).
std::string lastLines(const std::string& text, int n) {
    std::size_t at = text.size();
    if (at > 0 && text[at - 1] == '\n') --at;
    for (; n > 0; --n) {
        const std::size_t nl = at == 0 ? std::string::npos : text.rfind('\n', at - 1);
        if (nl == std::string::npos) return text;
        at = nl;
    }
    return text.substr(at + 1);
}

struct Rgb {
    std::vector<unsigned char> px;
    int w = 0, h = 0;
    explicit Rgb(const std::string& png) {
        int channels = 0;
        unsigned char* data = stbi_load(png.c_str(), &w, &h, &channels, 3);
        REQUIRE(data != nullptr);
        px.assign(data, data + std::size_t(3) * std::size_t(w) * std::size_t(h));
        stbi_image_free(data);
    }
    // Pixels within `tol` levels of a colour, in columns [x0, x1).
    std::size_t near(int r, int g, int b, int tol, int x0 = 0, int x1 = -1) const {
        std::size_t n = 0;
        for (int y = 0; y < h; ++y)
            for (int x = x0; x < (x1 < 0 ? w : x1); ++x) {
                const unsigned char* p = &px[3 * (std::size_t(y) * std::size_t(w) + std::size_t(x))];
                n += std::abs(p[0] - r) <= tol && std::abs(p[1] - g) <= tol && std::abs(p[2] - b) <= tol;
            }
        return n;
    }
};

// The background is (0.1, 0.1, 0.12) x 255.
std::size_t particlePixels(const Rgb& p, int x0 = 0) {
    const int cols = p.w - x0;
    return std::size_t(cols) * std::size_t(p.h) - p.near(26, 26, 31, 2, x0);
}

// Positions of one species in the last frame of an extended XYZ file (name in the first column).
std::vector<Eigen::Vector3d> positionsOf(const std::string& xyz, const std::string& species) {
    std::ifstream in(xyz);
    std::string line;
    std::vector<Eigen::Vector3d> all, last;
    while (std::getline(in, line)) {
        const std::size_t n = std::stoul(line);
        std::getline(in, line);  // the comment line
        all.clear();
        for (std::size_t i = 0; i < n && std::getline(in, line); ++i) {
            std::istringstream row(line);
            std::string name;
            Eigen::Vector3d p;
            row >> name >> p.x() >> p.y() >> p.z();
            if (name == species) all.push_back(p);
        }
        last = all;
    }
    return last;
}

double nearest(const std::vector<Eigen::Vector3d>& ps, const Eigen::Vector3d& x) {
    double best = 1e300;
    for (const auto& p : ps) best = std::min(best, (p - x).norm());
    return best;
}

}  // namespace

TEST_CASE("bop-viewer --headless writes the frames of a 2-rank server as pictures of its particles", "[net][gui]") {
    test::TempDir dir("viewer-headless");
    test::ChildProcess srv(server("bulk-box", {"--publish-hz", "20", "-o", dir.file("run")}));
    const std::string out = test::outputDir("viewer", "headless");
    const auto [code, printed] =
        test::runCommand(test::buildDir() + "/viz_client/bop-viewer " + srv.endpoint() +
                             " --headless --no-panel --frames 4 --width 320 --height 240 --out " + out + " 2>&1",
                         60s);
    INFO(printed);
    REQUIRE(code == 0);
    // Steps advance from frame to frame: the pictures are of a running server.
    std::vector<long long> steps;
    const std::regex line("frame [0-9]+: step ([0-9]+), 2048 particles");
    for (auto it = std::sregex_iterator(printed.begin(), printed.end(), line); it != std::sregex_iterator(); ++it)
        steps.push_back(std::stoll((*it)[1]));
    REQUIRE(steps.size() == 4);
    for (std::size_t k = 1; k < steps.size(); ++k) CHECK(steps[k] > steps[k - 1]);
    for (int k = 1; k <= 4; ++k) {
        const Rgb p(out + "/frame-00000" + std::to_string(k) + ".png");
        CHECK(p.w == 320);
        CHECK(p.h == 240);
        INFO("frame " << k << ": " << particlePixels(p) << " particle pixels");
        CHECK(particlePixels(p) > std::size_t(p.w * p.h) / 10);
    }
    srv.stop(SIGINT);
}

TEST_CASE("bop-viewer --headless draws the served torus bag from Compact8 frames (8 bytes a particle)", "[net][gui]") {
    test::TempDir dir("viewer-compact");
    const std::string start = test::builtTorus();
    const std::size_t particles =
        positionsOf(start, "torus-surface").size() + positionsOf(start, "torus-volume").size();
    test::ChildProcess srv(
        server("torus", {"--restart", start, "--compact", "--publish-hz", "10", "-o", dir.file("run")}));
    const std::string out = test::outputDir("viewer", "compact");
    const auto [code, printed] =
        test::runCommand(test::buildDir() + "/viz_client/bop-viewer " + srv.endpoint() +
                             " --headless --no-panel --frames 3 --width 320 --height 240 --out " + out + " 2>&1",
                         60s);
    INFO(printed);
    REQUIRE(code == 0);
    CHECK(printed.find("frame 3: step ") != std::string::npos);
    CHECK(printed.find(", " + std::to_string(particles) + " particles") != std::string::npos);
    const Rgb p(out + "/frame-000003.png");
    INFO(particlePixels(p) << " particle pixels");
    CHECK(particlePixels(p) > std::size_t(p.w * p.h) / 10);
    srv.stop(SIGINT);
}

TEST_CASE("a probe scripted in bop-viewer --headless indents the served torus bag and feels it push back",
          "[net][gui]") {
    test::TempDir dir("viewer-probe");
    // The torus as its construction timeline builds it (4,000 steps, one rank), then served.
    const std::string start = test::builtTorus();
    const std::vector<Eigen::Vector3d> before = positionsOf(start, "torus-surface");
    REQUIRE(before.size() > 500);
    Eigen::Vector3d top = before.front();
    for (const auto& p : before)
        if (p.z() > top.z()) top = p;
    // k0 = 2.5: the probe's own r0 is 2.5 r0 = 4.3 and its reach 1.6 times that, 6.9 (length).
    // From beyond its reach above the top of the tube down to 1.2 above the surface, in 2 s.
    const Eigen::Vector3d from = top + Eigen::Vector3d(0, 0, 8.5), to = top + Eigen::Vector3d(0, 0, 1.2);
    test::ChildProcess srv(server("torus", {"--restart", start, "--publish-hz", "10", "-o", dir.file("run")}));
    const std::string out = test::outputDir("viewer", "probe");
    const auto point = [](const Eigen::Vector3d& p) {
        std::ostringstream s;
        s << p.x() << ',' << p.y() << ',' << p.z();
        return s.str();
    };
    const auto [code, printed] = test::runCommand(
        test::buildDir() + "/viz_client/bop-viewer " + srv.endpoint() + " --headless --frames 30 --out " + out +
            " --probe-from " + point(from) + " --probe-to " + point(to) + " --probe-seconds 2 --probe-k0 2.5 2>&1",
        60s);
    INFO(printed);
    REQUIRE(code == 0);
    srv.stop(SIGINT);  // holds the probe where it ended until the state is written
    INFO(srv.output());
    REQUIRE(srv.output().find("final state:") != std::string::npos);

    // The reaction force from frames.csv: nothing while out of reach, then the surface pushes
    // the probe back up, against its motion, by more than a unit force.
    std::ifstream csv(out + "/frames.csv");
    std::string row;
    std::getline(csv, row);
    double firstForce = -1, peakUp = 0;
    while (std::getline(csv, row)) {
        std::vector<double> v;
        std::istringstream s(row.substr(row.find(',') + 1));
        for (std::string cell; std::getline(s, cell, ',');) v.push_back(std::stod(cell));
        REQUIRE(v.size() == 16);  // step .. map_frame after the picture's name
        const bool active = v[7] != 0;
        const Eigen::Vector3d force(v[11], v[12], v[13]);
        if (active && firstForce < 0) firstForce = force.norm();
        if (active) peakUp = std::max(peakUp, force.z());
        CHECK(v[14] > 0);   // the torus bag's cavity volume
        CHECK(v[15] == 0);  // one map: frame 0
    }
    INFO("first force " << firstForce << ", largest upward force " << peakUp);
    CHECK(firstForce >= 0);
    CHECK(firstForce < 0.05);
    CHECK(peakUp > 1.0);

    // The surface moved away from the probe: where it ended (1.2 above the old top) the nearest
    // surface particle was 1.2 away or closer; after the press none is within 2.
    const std::vector<Eigen::Vector3d> after = positionsOf(dir.file("run") + "/final.xyz", "torus-surface");
    INFO("nearest surface particle to the probe: " << nearest(before, to) << " before, " << nearest(after, to)
                                                   << " after");
    CHECK(nearest(before, to) <= 1.25);
    CHECK(nearest(after, to) > 2.0);
    // The last picture shows the probe (its yellow core) and the bag.
    const Rgb last(out + "/frame-000030.png");
    CHECK(last.near(255, 210, 60, 60) > 10);
    CHECK(particlePixels(last, int(0.4 * last.w)) > std::size_t(last.w * last.h) / 20);
}

TEST_CASE("bop-viewer reconnects on its own when the server is lost and another comes up on its port", "[net][gui]") {
    test::TempDir dir("viewer-reconnect");
    const std::string port = std::to_string(test::freeBasePort());  // both servers' (commands, frames, probes)
    std::vector<std::string> once = server("bulk-box", {"--publish-hz", "2", "-o", dir.file("a")});
    REQUIRE(once[6] == "--port");
    once[7] = port;
    auto first = std::make_unique<test::ChildProcess>(once);
    const std::string endpoint = first->endpoint();
    const std::string out = test::outputDir("viewer", "reconnect");
    std::pair<int, std::string> viewer;
    std::thread run([&] {
        viewer = test::runCommand(test::buildDir() + "/viz_client/bop-viewer " + endpoint +
                                      " --headless --no-panel --frames 6 " +
                                      "--width 160 --height 120 --lost-after 2 --out " + out + " 2>&1",
                                  120s);
    });
    // Frames from the first server, then it stops; a second one starts on the same port.
    const auto lines = [&] {
        std::ifstream csv(out + "/frames.csv");
        std::size_t n = 0;
        for (std::string l; std::getline(csv, l);) ++n;
        return n == 0 ? 0 : n - 1;
    };
    for (int k = 0; k < 300 && lines() < 2; ++k) std::this_thread::sleep_for(50ms);
    const int firstCode = first->stop(SIGINT);
    const std::string firstOutput = first->output();
    first.reset();
    // It holds its first step until the viewer is back, so its steps start again from 0.
    std::vector<std::string> again =
        server("bulk-box", {"--publish-hz", "2", "--wait-for-client", "-o", dir.file("b")});
    again[7] = port;
    std::unique_ptr<test::ChildProcess> second;
    std::string secondError;
    try {
        second = std::make_unique<test::ChildProcess>(again);
    } catch (const std::exception& e) {  // the viewer would wait for it forever: stop the viewer too
        secondError = e.what();
        test::runCommand("pkill -INT -f 'bop-viewer .*--out " + out + "'", 30s);
    }
    run.join();
    // The lines that say why, short enough to survive a CI log's cuts.
    INFO("the second server: " << (secondError.empty() ? "started" : lastLines(secondError, 4)));
    INFO("the first server (mpirun) stopped with " << firstCode << "; it printed last:\n" << lastLines(firstOutput, 4));
    REQUIRE(secondError.empty());
    INFO(viewer.second);
    REQUIRE(viewer.first == 0);
    CHECK(viewer.second.find("(connection 2)") != std::string::npos);
    // The steps start again after the reconnection: the second server's pictures follow the first's.
    std::vector<long long> steps;
    const std::regex line("frame [0-9]+: step ([0-9]+)");
    for (auto it = std::sregex_iterator(viewer.second.begin(), viewer.second.end(), line); it != std::sregex_iterator();
         ++it)
        steps.push_back(std::stoll((*it)[1]));
    REQUIRE(steps.size() == 6);
    CHECK(std::is_sorted(steps.begin(), steps.end()) == false);
    CHECK(steps.back() > steps[steps.size() - 2]);  // and go on from there
    second->stop(SIGINT);
}

TEST_CASE("the window viewer under Xvfb draws the served particles and its panel, and takes a screenshot",
          "[net][gui]") {
    if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) {
        WARN("xvfb-run is not installed (scripts/install-deps.sh installs it): the window is not tested here");
        return;
    }
    test::TempDir dir("viewer-window");
    test::ChildProcess srv(server("bulk-box", {"--publish-hz", "20", "-o", dir.file("run")}));
    const std::string shot = test::outputDir("viewer", "window") + "/window.png";
    const auto [code, printed] =
        test::runCommand("xvfb-run -a -s '-screen 0 1280x800x24' " + test::buildDir() + "/viz_client/bop-viewer " +
                             srv.endpoint() + " --frames 5 --width 800 --height 500 --screenshot " + shot + " 2>&1",
                         60s);
    INFO(printed);
    REQUIRE(code == 0);
    CHECK(printed.find("drew 5 new frames") != std::string::npos);
    const Rgb p(shot);
    CHECK(p.w == 800);
    CHECK(p.h == 500);
    // The panel's title bar (Dear ImGui's dark style, active title (41, 74, 122)) on the left,
    // particles right of the panel.
    const std::size_t title = p.near(41, 74, 122, 3, 0, 360);
    INFO(title << " title-bar pixels, " << particlePixels(p, 360) << " particle pixels right of the panel");
    CHECK(title > 2000);
    CHECK(particlePixels(p, 360) > std::size_t((800 - 360) * 500) / 10);
    srv.stop(SIGINT);
}

TEST_CASE("bop-viewer --headless cuts the served torus with a scripted blade: the server cuts, the pictures show it",
          "[net][gui][cut]") {
    test::TempDir dir("viewer-cut");
    // The placed torus (torus-cut.toml, settled at its start) served at 2 ranks; the blade of
    // 3.2 r0 drawn along x through the box's middle at mid-height crosses the tube twice.
    test::ChildProcess srv(server("torus-cut", {"--publish-hz", "10", "-o", dir.file("run")}));
    protocol::ClientSession c;
    const protocol::SceneInfo info = c.connect(srv.endpoint(), 20s);
    const Eigen::Vector3d mid = 0.5 * (info.boxLo + info.boxHi);
    const auto point = [](double x, double y, double z) {
        std::ostringstream s;
        s << x << ',' << y << ',' << z;
        return s.str();
    };
    const std::string out = test::outputDir("viewer", "cut");
    const auto [code, printed] = test::runCommand(
        test::buildDir() + "/viz_client/bop-viewer " + srv.endpoint() + " --headless --frames 30 --out " + out +
            " --probe-from " + point(info.boxLo.x(), mid.y(), mid.z()) + " --probe-to " +
            point(info.boxHi.x(), mid.y(), mid.z()) + " --probe-seconds 1 --probe-cut " +
            std::to_string(3.2 * info.r0) + " 2>&1",
        60s);
    INFO(printed);
    REQUIRE(code == 0);
    srv.stop(SIGINT);
    const std::string log = srv.output();
    INFO(log);
    REQUIRE(log.find("final state:") != std::string::npos);
    // Strokes of a radius each along the box's width: several cuts, particles taken out.
    std::size_t cuts = 0, taken = 0;
    const std::regex cutLine("cut [0-9]+ at step [0-9]+: ([0-9]+) particles out");
    for (auto it = std::sregex_iterator(log.begin(), log.end(), cutLine); it != std::sregex_iterator(); ++it)
        ++cuts, taken += std::stoul((*it)[1]);
    CHECK(cuts >= 3);
    CHECK(taken > 200);
    // The last picture holds the two pieces: fewer particles than the first frame's.
    std::ifstream csv(out + "/frames.csv");
    std::string row, first, last;
    std::getline(csv, row);
    while (std::getline(csv, row)) (first.empty() ? first : last) = row;
    const auto particlesOf = [](const std::string& r) {  // column 8: particles
        std::istringstream s(r);
        std::string cell;
        for (int k = 0; k < 8; ++k) std::getline(s, cell, ',');
        return std::stoul(cell);
    };
    INFO("frames: first " << first << ", last " << last);
    CHECK(particlesOf(last) + 200 < particlesOf(first));
}
