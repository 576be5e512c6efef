// bop-render-bench: milliseconds per frame of the viewer's renderer against particle count, drawn
// headless (EGL) into an offscreen target; scripts/bench/render.sh runs it. The bags are
// synthetic tori (scene/SyntheticBag.hpp) sized to about the asked particle counts.
#include "app/EglHeadless.hpp"
#include "bop/common/ToolMain.hpp"
#include "render/Gl.hpp"
#include "render/InstanceRenderer.hpp"
#include "render/Offscreen.hpp"
#include "scene/Instances.hpp"
#include "scene/SyntheticBag.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    return bop::runTool("bop-render-bench", [&] {
        CLI::App app{"bop-render-bench: ms per frame of the viewer's renderer (headless, EGL) against particle count"};
        std::vector<long long> counts{10000, 100000, 1000000};
        int frames = 10, width = 1280, height = 720;
        app.add_option("--particles", counts, "particle counts to draw (about; synthetic torus bags)")->delimiter(',');
        app.add_option("--frames", frames, "frames drawn per count; the median is reported")
            ->check(CLI::Range(1, 10000));
        app.add_option("--width", width, "picture width, pixels")->check(CLI::Range(16, 8192));
        app.add_option("--height", height, "picture height, pixels")->check(CLI::Range(16, 8192));
        CLI11_PARSE(app, argc, argv);
        bop::viz::EglHeadless gl;
        std::printf("renderer %s | %s\n", gl.renderer().c_str(), gl.version().c_str());
        bop::viz::Offscreen target(width, height);
        bop::viz::InstanceRenderer renderer;
        const double r0 = std::sqrt(3.0), pi = std::numbers::pi;
        for (const long long n : counts) {
            // Tube radius a = R / 3: about 2 pi^2 a^2 R / r0^3 = 2 pi^2 R^3 / (9 r0^3) particles.
            const double R = r0 * std::cbrt(9.0 * double(n) / (2 * pi * pi)), a = R / 3;
            const auto scene = bop::viz::torusBagScene(R, a, r0, {220, 40, 30, 255}, {30, 60, 200, 255});
            const auto frame = bop::viz::torusBag(R, a, r0);
            bop::viz::OrbitCamera cam;
            cam.fit(Eigen::AlignedBox3d(scene.boxLo, scene.boxHi), double(width) / height);
            bop::viz::Instances in;
            std::vector<double> build, draw;
            for (int k = 0; k < frames; ++k) {
                auto t0 = Clock::now();
                bop::viz::buildInstances(frame, scene, {}, in);
                build.push_back(msSince(t0));
                t0 = Clock::now();
                renderer.draw(in, cam, width, height, {0.1f, 0.1f, 0.12f});
                glFinish();  // the frame is drawn, not only queued
                draw.push_back(msSince(t0));
                cam.orbit(0.05, 0.0);
            }
            const double ms = median(build) + median(draw);
            std::printf("particles %zu surfels %zu spheres %zu build_ms %.2f draw_ms %.2f frame_ms %.2f fps %.1f\n",
                        frame.count(), in.surfels.size(), in.spheres.size(), median(build), median(draw), ms,
                        1000.0 / ms);
            std::fflush(stdout);
        }
        return 0;
    });
}
