// bop-viewer: watches a served run. So far only headless (--headless): frames are drawn through
// EGL into an offscreen target and written as PNG files; the window (GLFW) and the panel (Dear
// ImGui) are to come (docs/viewer.md).
#include "app/EglHeadless.hpp"
#include "client/ClientSession.hpp"
#include "render/InstanceRenderer.hpp"
#include "render/Offscreen.hpp"
#include "scene/Instances.hpp"

#include "bop/common/Canvas.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/ToolMain.hpp"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

namespace {

using namespace bop;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr std::array<float, 3> kBackground{0.1f, 0.1f, 0.12f};  // RGB 0..1
constexpr auto kLostAfter = 10s;  // no frame for this long: the server is taken as lost

// Connects, retrying with a doubling wait (1 s, 2 s, ... at most 8 s) until `limit` has passed.
protocol::SceneInfo connectWithBackoff(protocol::ClientSession& c, const std::string& endpoint, double limitS) {
    const auto end = Clock::now() + std::chrono::duration<double>(limitS);
    auto wait = 1s;
    for (int attempt = 1;; ++attempt) {
        try {
            return c.connect(endpoint, wait);
        } catch (const Error& e) {
            if (Clock::now() + wait > end) throw;
            std::printf("bop-viewer: %s; trying again (attempt %d)\n", e.what(), attempt + 1);
            std::fflush(stdout);
            wait = std::min(2 * wait, std::chrono::seconds(8));
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    return runTool("bop-viewer", [&] {
        CLI::App app{"bop-viewer: watches a served BoP run (bop-server). Headless: frames drawn through EGL and "
                     "written as PNG files"};
        std::string endpoint, outDir = "out/viewer";
        bool headless = false;
        int frames = 10, width = 960, height = 540;
        double wantedHz = 0, connectS = 30;
        app.add_option("endpoint", endpoint, "the server's control endpoint, tcp://HOST:PORT")->required();
        app.add_flag("--headless", headless, "no window: draw through EGL into PNG files");
        app.add_option("--frames", frames, "frames to write, then exit")->check(CLI::Range(1, 1000000));
        app.add_option("--out", outDir, "folder of the PNG files (frame-000001.png, ...)");
        app.add_option("--width", width, "picture width, pixels")->check(CLI::Range(16, 8192));
        app.add_option("--height", height, "picture height, pixels")->check(CLI::Range(16, 8192));
        app.add_option("--fps", wantedHz, "frames per second wanted from the server (0: all it publishes)")
            ->check(CLI::Range(0.0, 1000.0));
        app.add_option("--connect-timeout", connectS, "give up connecting after this long, s")->check(CLI::PositiveNumber);
        CLI11_PARSE(app, argc, argv);
        if (!headless)
            throw Error("bop-viewer", "the window viewer (GLFW, Dear ImGui) is not built yet; run with --headless");

        viz::EglHeadless gl;
        viz::Offscreen target(width, height);
        viz::InstanceRenderer renderer;
        std::filesystem::create_directories(outDir);
        protocol::ClientOptions o;
        o.clientName = "bop-viewer";
        o.frameRateHz = float(wantedHz);
        protocol::ClientSession session(o);
        protocol::SceneInfo scene = connectWithBackoff(session, endpoint, connectS);
        std::printf("bop-viewer: connected to %s: %llu particles, %zu species; drawing with %s\n", endpoint.c_str(),
                    (unsigned long long)scene.particleCount, scene.species.size(), gl.renderer().c_str());
        viz::OrbitCamera camera;
        const double aspect = double(width) / height;
        camera.fit(Eigen::AlignedBox3d(scene.boxLo, scene.boxHi), aspect);
        session.startReceiver();
        viz::Instances instances;
        std::uint64_t seen = 0;
        auto lastFrame = Clock::now();
        for (int written = 0; written < frames;) {
            const protocol::LatestFrame latest = session.latestFrame();
            if (!latest.frame || latest.count == seen) {
                if (Clock::now() - lastFrame > kLostAfter) {  // lost: connect again, the receiver with it
                    std::printf("bop-viewer: no frame for %lld s; reconnecting\n", (long long)(kLostAfter / 1s));
                    scene = connectWithBackoff(session, endpoint, connectS);
                    session.startReceiver();
                    seen = 0;
                    lastFrame = Clock::now();
                }
                std::this_thread::sleep_for(5ms);
                continue;
            }
            seen = latest.count;
            lastFrame = Clock::now();
            const auto t0 = Clock::now();
            viz::buildInstances(*latest.frame, scene, {}, instances);
            target.bind();
            renderer.draw(instances, camera, width, height, kBackground);
            char name[32];
            std::snprintf(name, sizeof name, "frame-%06d.png", ++written);
            Canvas::fromRgb(width, height, target.readRgb()).writePng((std::filesystem::path(outDir) / name).string());
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            std::printf("frame %d: step %llu, %zu particles, drawn and written in %.1f ms\n", written,
                        (unsigned long long)latest.frame->step, latest.frame->count(), ms);
            std::fflush(stdout);
        }
        std::printf("bop-viewer: %d frames in %s\n", frames, outDir.c_str());
        return 0;
    });
}
