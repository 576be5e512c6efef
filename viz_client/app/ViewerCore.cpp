#include "app/ViewerCore.hpp"

#include "scene/SceneBags.hpp"

#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

namespace bop::viz {
namespace {

constexpr std::array<float, 3> kBackground{0.1f, 0.1f, 0.12f};  // RGB 0..1
constexpr double kOrbitRadPerNdc = 2.0;                         // a drag across the view turns 4 rad
constexpr double kZoomPerNotch = 0.9;

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

}  // namespace

ViewerCore::ViewerCore(ViewerLink& link) : link_(link) {}

void ViewerCore::newScene(const protocol::SceneInfo& s) {
    controls_ = Controls(s);
    camera.fit(Eigen::AlignedBox3d(s.boxLo, s.boxHi), aspect_);
    fitPending_ = true;  // to the particles, once a frame has come
    probe = MouseProbe(0.25 * s.r0);
    panel.birthOn.assign(s.species.size() + 1, false);
    panel.filter.hiddenSpecies.assign(s.species.size() + 1, false);
    for (const std::string& name : hideByName(panel.filter, s, panel.hideAtStart)) {
        std::string known;
        for (const BagEntry& b : bagsOfScene(s)) known += " '" + b.name + "'";
        std::fprintf(stderr, "bop-viewer: --hide '%s': the scene has no bag or species of that name (bags:%s)\n",
                     name.c_str(), known.c_str());
    }
}

bool ViewerCore::poll(double nowS) {
    const LinkStatus st = link_.status();
    if (st.sceneVersion != sceneVersion_) {
        sceneVersion_ = st.sceneVersion;
        scene_ = link_.scene();
        if (scene_) newScene(*scene_);  // frame counts go on across connections: nothing to reset
    }
    if (nowS - lastCommandsS_ > 0.1) {
        lastCommandsS_ = nowS;
        for (protocol::Command& c : controls_.commands()) link_.submit(std::move(c));
    }
    const protocol::LatestFrame latest = link_.latestFrame();
    if (!scene_ || !latest.frame || latest.count == seenFrames_) return false;
    seenFrames_ = latest.count;
    frame_ = latest.frame;
    received_.tick(nowS);
    lastFrameS_ = nowS;
    const protocol::StateFrame& f = *frame_;
    perSpecies_.assign(scene_->species.size() + 1, 0);
    for (std::uint8_t s : f.species)
        if (s < perSpecies_.size()) ++perSpecies_[s];
    plots_.push(
        {f.simTime, f.stats.kinetic + f.stats.potential, f.stats.pressure, f.probeForce.norm(), f.stats.cavityVolume});
    return true;
}

void ViewerCore::draw(int width, int height, double nowS, bool showPanel, const std::function<void()>& platformFrame) {
    aspect_ = double(width) / double(height);
    ImGui_ImplOpenGL3_NewFrame();
    platformFrame();
    ImGui::NewFrame();
    if (showPanel) {
        const LinkStatus st = link_.status();
        PanelFigures fig{&st,
                         scene_.get(),
                         frame_.get(),
                         perSpecies_,
                         received_.rateHz(nowS),
                         drawn_.rateHz(nowS),
                         frame_ ? nowS - lastFrameS_ : 0.0,
                         &plots_};
        drawPanel(panel, controls_, link_, fig);
    }
    ImGui::Render();
    if ((panel.fitRequested || fitPending_) && frame_) {
        fit(showPanel ? kPanelWidthPx / double(width) : 0.0);
        fitPending_ = false;
    }
    if (panel.resetRequested) camera.reset();
    panel.fitRequested = panel.resetRequested = false;
    panel.filter.cut.reset();
    if (panel.cutOn && scene_)
        panel.filter.cut =
            CutPlane{camera.target() + panel.cutOffsetR0 * scene_->r0 * camera.forward(), -camera.forward()};
    if (frame_ && scene_) {
        buildInstances(*frame_, *scene_, panel.filter, instances_);
    } else {
        instances_.surfels.clear();
        instances_.spheres.clear();
    }
    std::optional<ProbeMarker> marker;
    if (scene_ && (probe.active() || (frame_ && frame_->probeActive))) {
        // The server's probe when it has one (a haptic client's, or ours as applied), else ours.
        const Eigen::Vector3d at = frame_ && frame_->probeActive ? frame_->probePosition : probe.position();
        marker = probeMarker(at, scene_->probeReach * controls_.now.k0, scene_->r0, true);
        instances_.spheres.push_back(marker->core);
    }
    renderer_.draw(instances_, camera, width, height, kBackground);
    if (marker) renderer_.drawTranslucent({marker->reach}, camera, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    drawn_.tick(nowS);
}

void ViewerCore::fit(double panelFraction) {
    const std::vector<float>& p = frame_->positions;
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i + 2 < p.size(); i += 3) box.extend(Eigen::Vector3d(p[i], p[i + 1], p[i + 2]));
    if (box.isEmpty() && scene_) box = Eigen::AlignedBox3d(scene_->boxLo, scene_->boxHi);
    // The free part of the view, right of the panel, is narrower: fit to it, then centre on it.
    camera.fit(box, aspect_ * (1 - panelFraction));
    camera.pan(panelFraction, 0, aspect_);
}

void ViewerCore::sendProbe() {
    if (!probe.changed()) return;
    link_.setProbe(probe.message(nowNs(), controls_.now.k0, controls_.now.k1));
}

void ViewerCore::scriptProbe(const Eigen::Vector3d& position, bool active) {
    probe.place(position, active);
    sendProbe();
}

void ViewerCore::scriptCut(const Eigen::Vector3d& position, double radius) {
    if (bladeAt_ && (position - *bladeAt_).norm() < radius) return;
    link_.submit(cutCommand(bladeAt_ ? *bladeAt_ : position, position, radius));
    bladeAt_ = position;
}

void ViewerCore::setProbeParameters(double k0, double k1) {
    if (k0 > 0) controls_.now.k0 = k0;
    if (k1 > 0) controls_.now.k1 = k1;
}

void ViewerCore::press(int button, double x, double y, double aspect) {
    dragButton_ = button;
    lastX_ = x, lastY_ = y;
    if (button != 0) return;
    if (panel.tool == MouseTool::Probe) {
        probe.press(x, y, camera, aspect);
        sendProbe();
    } else if (panel.tool == MouseTool::Seed) {
        link_.submit(seedCommand(panel.seedSpecies, camera.onViewPlane(x, y, camera.target(), aspect)));
    } else if (panel.tool == MouseTool::Cut && scene_) {
        bladeAt_.reset();
        scriptCut(camera.onViewPlane(x, y, camera.target(), aspect), panel.bladeR0 * scene_->r0);
    }
}

void ViewerCore::move(double x, double y, double aspect) {
    if (dragButton_ == 1) {
        camera.pan(x - lastX_, y - lastY_, aspect);
    } else if (dragButton_ == 0 && panel.tool == MouseTool::Probe) {
        probe.drag(x, y, camera, aspect);
        sendProbe();
    } else if (dragButton_ == 0 && panel.tool == MouseTool::Cut && scene_) {
        scriptCut(camera.onViewPlane(x, y, camera.target(), aspect), panel.bladeR0 * scene_->r0);
    } else if (dragButton_ == 0 && panel.tool == MouseTool::View) {
        camera.orbit(-kOrbitRadPerNdc * (x - lastX_), -kOrbitRadPerNdc * (y - lastY_));
    }
    lastX_ = x, lastY_ = y;
}

void ViewerCore::release(int button) {
    if (button == 0 && panel.tool == MouseTool::Probe) {
        probe.release();
        sendProbe();
    }
    dragButton_ = -1;
}

void ViewerCore::scroll(double notches) {
    if (panel.tool == MouseTool::Probe && probe.active()) {
        probe.wheel(notches, camera);  // wheel forward (up) pushes the probe into the scene
        sendProbe();
    } else {
        camera.zoom(std::pow(kZoomPerNotch, notches));
    }
}

void ViewerCore::key(char k) {
    switch (k) {
        case 'F':
            panel.fitRequested = true;
            break;
        case 'R':
            panel.resetRequested = true;
            break;
        case 'P':
            panel.paused = !panel.paused;
            link_.submit(runCommand(panel.paused ? protocol::RunAction::Pause : protocol::RunAction::Resume));
            break;
        case 'N':
            if (panel.paused)
                link_.submit(runCommand(protocol::RunAction::SingleStep, std::uint32_t(panel.singleSteps)));
            break;
        case 'S':
            panel.screenshotRequested = true;
            break;
        default:
            break;
    }
}

bool ViewerCore::takeScreenshotRequest() {
    const bool r = panel.screenshotRequested;
    panel.screenshotRequested = false;
    return r;
}

}  // namespace bop::viz
