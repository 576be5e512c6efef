// bop-viewer --headless: the window's drawing without a window (EGL on Mesa's surfaceless
// platform), each new frame written as a PNG file and a line of frames.csv.
#include "app/EglHeadless.hpp"
#include "app/ViewerCore.hpp"
#include "app/ViewerLoops.hpp"
#include "bop/common/Canvas.hpp"
#include "bop/common/Error.hpp"
#include "render/Offscreen.hpp"

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

namespace bop::viz {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int runHeadless(ViewerLink& link, const LoopOptions& o) {
    EglHeadless gl;
    Offscreen target(o.width, o.height);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the pictures
    ImGui_ImplOpenGL3_Init("#version 330 core");
    {
        ViewerCore core(link);
        core.panel.hideAtStart = o.hide;
        std::filesystem::create_directories(o.outDir);
        std::ofstream csv(std::filesystem::path(o.outDir) / "frames.csv");
        csv << "picture,step,sim_time,kinetic_energy,potential_energy,pressure,step_rate_hz,particles,"
               "probe_active,probe_x,probe_y,probe_z,probe_fx,probe_fy,probe_fz,cavity_volume,map_frame\n";
        const auto t0 = Clock::now();
        std::optional<double> firstFrameS;
        double lastS = 0;
        std::printf("bop-viewer: drawing headless with %s\n", gl.renderer().c_str());
        LinkState shown = LinkState::Connecting;
        std::uint64_t connections = 0;
        for (int written = 0; written < o.frames;) {
            const double now = secondsSince(t0);
            const LinkStatus st = link.status();
            if (st.state == LinkState::GaveUp) throw Error("bop-viewer", st.message);
            if (st.state != shown || st.sceneVersion != connections) {  // what the panel shows, on the console
                shown = st.state;
                connections = st.sceneVersion;
                std::printf("bop-viewer: %s (connection %llu): %s\n", linkStateName(st.state),
                            (unsigned long long)connections, st.message.c_str());
                std::fflush(stdout);
            }
            if (!core.poll(now)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            if (!firstFrameS) {
                firstFrameS = now;
                if (o.probe) core.setProbeParameters(o.probe->k0, o.probe->k1);
            }
            if (o.probe) {
                const double u = std::min(1.0, (now - *firstFrameS) / std::max(o.probe->seconds, 1e-9));
                const Eigen::Vector3d at = o.probe->from + u * (o.probe->to - o.probe->from);
                if (o.probe->cutRadius > 0)
                    core.scriptCut(at, o.probe->cutRadius);
                else
                    core.scriptProbe(at, true);
            }
            const auto t1 = Clock::now();
            target.bind();
            core.draw(o.width, o.height, now, o.panel, [&] {
                ImGuiIO& io = ImGui::GetIO();
                io.DisplaySize = ImVec2(float(o.width), float(o.height));
                io.DeltaTime = float(std::max(now - lastS, 1e-3));
            });
            lastS = now;
            char name[32];
            std::snprintf(name, sizeof name, "frame-%06d.png", ++written);
            const Canvas picture = Canvas::fromRgb(o.width, o.height, target.readRgb());
            picture.writePng((std::filesystem::path(o.outDir) / name).string());
            if (written == o.frames && !o.screenshot.empty()) picture.writePng(o.screenshot);
            const protocol::StateFrame& f = *core.frame();
            csv << name << ',' << f.step << ',' << f.simTime << ',' << f.stats.kinetic << ',' << f.stats.potential
                << ',' << f.stats.pressure << ',' << f.stats.stepRateHz << ',' << f.count() << ',' << int(f.probeActive)
                << ',' << f.probePosition.x() << ',' << f.probePosition.y() << ',' << f.probePosition.z() << ','
                << f.probeForce.x() << ',' << f.probeForce.y() << ',' << f.probeForce.z() << ',' << f.stats.cavityVolume
                << ',' << f.stats.mapFrame << std::endl;  // whole lines for whoever follows the file
            std::printf("frame %d: step %llu, %zu particles, probe force %.4g, drawn and written in %.1f ms\n", written,
                        (unsigned long long)f.step, f.count(), f.probeForce.norm(),
                        1000 * std::chrono::duration<double>(Clock::now() - t1).count());
            std::fflush(stdout);
        }
        std::printf("bop-viewer: %d frames and frames.csv in %s\n", o.frames, o.outDir.c_str());
        const protocol::ClientStats c = link.status().client;
        std::printf(
            "bop-viewer: frames received whole %llu, lost %llu (%llu of them sent as datagrams, from %llu "
            "datagrams read), malformed %llu, inconsistent %llu\n",
            (unsigned long long)c.framesReceived, (unsigned long long)(c.framesLost + c.udpFramesLost),
            (unsigned long long)c.udpFramesLost, (unsigned long long)c.udpDatagrams, (unsigned long long)c.malformed,
            (unsigned long long)c.inconsistentFrames);
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext();
    return 0;
}

}  // namespace bop::viz
