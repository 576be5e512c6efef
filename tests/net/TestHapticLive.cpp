// bop-haptic against a served torus bag (2 ranks): a scripted poke feels a reaction that opposes
// the poke and grows with depth, and moves the bag's surface; a server stopped mid-poke leaves
// the device without force within 50 ms, and one restarted on its port is connected to again;
// a simulated fingertip pressed on the bag comes to rest.
// Traces stay in build/test-output/haptic/.
#include "NetTestUtil.hpp"
#include "TestUtil.hpp"
#include "client/ClientSession.hpp"

#include <Eigen/Core>
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <thread>

using namespace bop;
using namespace std::chrono_literals;

namespace {

std::vector<std::string> torusServer(const std::string& outDir) {
    return {test::mpiexec(),
            "-np",
            "2",
            "--oversubscribe",
            test::buildDir() + "/dynamics_server/bop-server",
            test::sourceDir() + "/config/scenes/torus.toml",
            "--restart",
            test::builtTorus(),
            "--port",
            "0",
            "--publish-hz",
            "10",
            "--frame-ids",
            "-o",
            outDir};
}

// Surface particles (species 1) by id.
std::map<std::uint64_t, Eigen::Vector3d> surfaceById(const protocol::StateFrame& f) {
    std::map<std::uint64_t, Eigen::Vector3d> m;
    for (std::size_t i = 0; i < f.count(); ++i)
        if (f.species[i] == 1)
            m[f.ids[i]] = Eigen::Vector3d(f.positions[3 * i], f.positions[3 * i + 1], f.positions[3 * i + 2]);
    return m;
}

std::string haptic(const std::string& endpoint, const std::string& args) {
    return test::buildDir() + "/haptic_client/bop-haptic " + endpoint + " " + args + " 2>&1";
}

// Rows of a CSV with a header line, by column name.
struct Csv {
    std::vector<std::string> names;
    std::vector<std::vector<double>> rows;
    explicit Csv(const std::string& path) {
        std::ifstream in(path);
        std::string line;
        REQUIRE(std::getline(in, line));
        std::istringstream h(line);
        for (std::string c; std::getline(h, c, ',');) names.push_back(c);
        while (std::getline(in, line)) {
            std::vector<double> r;
            std::istringstream s(line);
            for (std::string c; std::getline(s, c, ',');) r.push_back(std::stod(c));
            rows.push_back(std::move(r));
        }
    }
    std::size_t col(const std::string& name) const {
        const auto it = std::find(names.begin(), names.end(), name);
        REQUIRE(it != names.end());
        return std::size_t(it - names.begin());
    }
};

// The rows of a trace still being written whose 20 cells all read as numbers (the last line may
// be cut short).
std::vector<std::vector<double>> wholeRows(const std::string& trace) {
    std::ifstream in(trace);
    std::string line;
    std::getline(in, line);
    std::vector<std::vector<double>> rows;
    while (std::getline(in, line)) {
        std::vector<double> r;
        std::istringstream s(line);
        try {
            for (std::string c; std::getline(s, c, ',');) r.push_back(std::stod(c));
        } catch (const std::exception&) {
            continue;
        }
        if (r.size() == 20) rows.push_back(std::move(r));
    }
    return rows;
}

// Waits (up to 30 s) until the trace, written as the loop runs, holds `rows` rows from the
// `afterS`-th second on with a force above 0.5 N on the device.
void waitUntilPushing(const std::string& trace, std::size_t rows, double afterS = 0) {
    const auto pushing = [&] {
        std::size_t found = 0;
        for (const auto& r : wholeRows(trace)) found += r[0] > afterS && r[16] > 0.5;  // t_s, force_n
        return found >= rows;
    };
    for (int k = 0; k < 300 && !pushing(); ++k) std::this_thread::sleep_for(100ms);
}

}  // namespace

TEST_CASE("bop-haptic pokes the served torus: the reaction opposes the poke, grows with depth, and moves the surface",
          "[net][haptic]") {
    test::TempDir dir("haptic-poke");
    test::ChildProcess srv(torusServer(dir.file("run")));
    const std::string out = test::outputDir("haptic", "poke");
    // A watcher: the surface before the poke, and how far the poke moves it near the probe.
    protocol::ClientSession watcher;
    watcher.connect(srv.endpoint(), 20s);
    std::optional<protocol::StateFrame> first;
    for (int k = 0; k < 50 && !first; ++k) first = watcher.receiveFrame(200ms);
    REQUIRE(first);
    const auto before = surfaceById(*first);
    std::atomic<bool> done{false};
    std::pair<int, std::string> result;
    std::thread run([&] {
        result = test::runCommand(
            haptic(srv.endpoint(), "--device sim:poke --standoff 3 --depth 1.5 --speed 1 --hold 1 --out " + out), 60s);
        done = true;
    });
    // The surface gives way: at the probe's deepest frame, the nearest surface particle to the
    // probe against the nearest one there before the poke.
    const auto nearestTo = [](const std::map<std::uint64_t, Eigen::Vector3d>& ps, const Eigen::Vector3d& x) {
        double best = 1e300;
        for (const auto& [id, p] : ps) best = std::min(best, (p - x).norm());
        return best;
    };
    double deepest = 1e300, clearBefore = 0, clearDuring = 0;
    while (!done)
        if (const auto f = watcher.receiveFrame(200ms); f && f->probeActive && f->probePosition.z() < deepest) {
            deepest = f->probePosition.z();
            clearBefore = nearestTo(before, f->probePosition);
            clearDuring = nearestTo(surfaceById(*f), f->probePosition);
        }
    run.join();
    const auto& [code, printed] = result;
    INFO(printed);
    REQUIRE(code == 0);
    srv.stop(SIGINT);
    INFO("nearest surface particle to the deepest probe: " << clearBefore << " before the poke, " << clearDuring
                                                           << " during it");
    CHECK(clearDuring > clearBefore + 0.2);                         // 0.88 -> 1.26 here
    CHECK(printed.find("gradient map 100%") != std::string::npos);  // downloaded at connect
    // The stiffness curve: force felt against the poke, by depth past the surface.
    const Csv curve(out + "/stiffness.csv");
    REQUIRE(curve.rows.size() >= 20);
    // Grows with depth: in steps of 0.25 (five bins of 0.05 averaged), each at least the last.
    // The live reaction adds noise: where particles close round the probe it pulls back, by up
    // to a tenth of the largest force for a while.
    std::vector<double> steps;
    for (std::size_t k = 0; k + 5 <= curve.rows.size(); k += 5) {
        double sum = 0;
        for (std::size_t j = k; j < k + 5; ++j) sum += curve.rows[j][1];
        steps.push_back(sum / 5);
    }
    const double top = *std::max_element(steps.begin(), steps.end());
    for (std::size_t k = 1; k < steps.size(); ++k) {
        INFO("depth " << 0.25 * double(k) << ".." << 0.25 * double(k + 1) << ": force " << steps[k]);
        CHECK(steps[k] > steps[k - 1] - 0.1 * top);  // a tenth of the largest for that pull
    }
    CHECK(steps.back() > 3 * steps.front());
    CHECK(curve.rows.back()[1] > 1.0);                        // opposes the poke, clearly, at the bottom
    CHECK(curve.rows.back()[1] > 5 * curve.rows.front()[1]);  // and far more than at the surface
    CHECK(std::filesystem::file_size(out + "/stiffness.png") > 1000);
    // The server's own reaction pushed the probe back out (up) while it was in.
    const Csv trace(out + "/haptic-trace.csv");
    // (Deeper in, particles close around an LJ probe and pull it slightly: the map's field
    // carries the stiffness there, as in the paper, which felt the field.)
    double serverUp = 0;
    for (const auto& r : trace.rows) serverUp = std::max(serverUp, r[trace.col("server_fz")]);
    INFO("largest upward reaction from the server " << serverUp);
    CHECK(serverUp > 0.1);
}

TEST_CASE("bop-haptic: a server stopped mid-poke leaves the device without force within 50 ms", "[net][haptic]") {
    test::TempDir dir("haptic-safety");
    test::ChildProcess srv(torusServer(dir.file("run")));
    const std::string out = test::outputDir("haptic", "safety");
    std::pair<int, std::string> result;
    std::thread run([&] {
        result = test::runCommand(haptic(srv.endpoint(),
                                         "--device sim:poke --standoff 3 --depth 1.5 --speed 1 --hold 10 "
                                         "--seconds 8 --out " +
                                             out),
                                  60s);
    });
    // Wait until the device pushes back, then stop the server.
    waitUntilPushing(out + "/haptic-trace.csv", 1);
    std::this_thread::sleep_for(500ms);
    srv.stop(SIGTERM);
    run.join();
    INFO(result.second);
    REQUIRE(result.first == 0);
    const Csv trace(out + "/haptic-trace.csv");
    const std::size_t t = trace.col("t_s"), n = trace.col("force_n"), age = trace.col("feedback_age_ms");
    // The last tick with fresh feedback, then the first with no force.
    std::size_t last = 0;
    for (std::size_t k = 0; k < trace.rows.size(); ++k)
        if (trace.rows[k][age] < 5) last = k;
    REQUIRE(last > 0);
    REQUIRE(last + 100 < trace.rows.size());  // the server went before the loop ended
    INFO("force before the silence " << trace.rows[last][n] << " N");
    CHECK(trace.rows[last][n] > 0.05);  // it was pushing
    std::size_t zero = last;
    while (zero < trace.rows.size() && trace.rows[zero][n] > 0) ++zero;
    REQUIRE(zero < trace.rows.size());
    const double ms = 1000 * (trace.rows[zero][t] - trace.rows[last][t]);
    INFO("force at 0 " << ms << " ms after the last feedback");
    CHECK(ms <= 50);
    for (std::size_t k = zero; k < trace.rows.size(); ++k) CHECK(trace.rows[k][n] == 0);  // and stays there
}

TEST_CASE("bop-haptic connects again on its own when the server restarts on its port, and feels it push back",
          "[net][haptic]") {
    test::TempDir dir("haptic-reconnect");
    const std::string port = std::to_string(test::freeBasePort());  // both servers' (commands, frames, probes)
    std::vector<std::string> once = torusServer(dir.file("a"));
    REQUIRE(once[8] == "--port");
    once[9] = port;
    auto first = std::make_unique<test::ChildProcess>(once);
    const std::string endpoint = first->endpoint();
    const std::string out = test::outputDir("haptic", "reconnect");
    test::ChildProcess client(
        {test::buildDir() + "/haptic_client/bop-haptic", endpoint, "--device", "sim:poke", "--standoff", "3", "--depth",
         "1.5", "--speed", "1", "--hold", "60", "--reconnect-after", "1", "--out", out},
        30s, "bop-haptic: sim:poke at");
    waitUntilPushing(out + "/haptic-trace.csv", 1);
    first->stop(SIGTERM);
    first.reset();
    // The same scene from the same checkpoint on the same port.
    std::vector<std::string> again = torusServer(dir.file("b"));
    again[9] = port;
    test::ChildProcess second(again);
    // Once the client says it is back: half a second of pushing from then on.
    for (int k = 0; k < 300 && client.output().find("connected again") == std::string::npos; ++k)
        std::this_thread::sleep_for(100ms);
    const auto rows = wholeRows(out + "/haptic-trace.csv");
    REQUIRE(!rows.empty());
    waitUntilPushing(out + "/haptic-trace.csv", 500, rows.back()[0]);
    REQUIRE(client.stop(SIGINT) == 0);
    second.stop(SIGTERM);
    const std::string printed = client.output();
    INFO(printed);
    CHECK(printed.find("connected again to " + endpoint + " (connection 2)") != std::string::npos);
    CHECK(printed.find("reconnections: 1") != std::string::npos);
    const Csv trace(out + "/haptic-trace.csv");
    const std::size_t t = trace.col("t_s"), n = trace.col("force_n"), age = trace.col("feedback_age_ms");
    // The longest gap without feedback, then fresh feedback and force again from the second server.
    double gapMs = 0, gapEnd = 0, lastFresh = -1, pushedAfter = 0;
    for (const auto& r : trace.rows)
        if (r[age] < 5) {
            if (lastFresh >= 0 && 1000 * (r[t] - lastFresh) > gapMs) gapMs = 1000 * (r[t] - lastFresh), gapEnd = r[t];
            lastFresh = r[t];
        }
    for (const auto& r : trace.rows)
        if (r[t] > gapEnd && r[age] < 5) pushedAfter = std::max(pushedAfter, r[n]);
    INFO("longest gap in feedback " << gapMs << " ms, to " << gapEnd << " s; largest force after it " << pushedAfter
                                    << " N");
    CHECK(gapMs > 1000);
    CHECK(pushedAfter > 0.5);
}

TEST_CASE("bop-haptic sim:finger pressed on the served torus comes to rest at its surface", "[net][haptic]") {
    test::TempDir dir("haptic-finger");
    test::ChildProcess srv(torusServer(dir.file("run")));
    const std::string out = test::outputDir("haptic", "finger");
    const auto [code, printed] = test::runCommand(
        haptic(srv.endpoint(), "--device sim:finger --standoff 3 --depth 1.5 --speed 1 --hold 3 --out " + out), 60s);
    INFO(printed);
    REQUIRE(code == 0);
    srv.stop(SIGINT);
    const Csv trace(out + "/haptic-trace.csv");
    const std::size_t t = trace.col("t_s"), z = trace.col("device_z"), n = trace.col("force_n");
    // The hold lasts from 4.5 s to 7.5 s: its last second.
    double lo = 1e9, hi = -1e9, force = 0;
    std::size_t count = 0;
    for (const auto& r : trace.rows)
        if (r[t] > 6.4 && r[t] < 7.4) lo = std::min(lo, r[z]), hi = std::max(hi, r[z]), force += r[n], ++count;
    REQUIRE(count > 500);
    INFO("fingertip z " << lo << " .. " << hi << ", mean force " << force / double(count) << " N");
    CHECK(hi - lo < 0.05);                // at rest: within 0.05 length over a second
    CHECK(force / double(count) > 0.05);  // pressed on the bag, which pushes back
}
