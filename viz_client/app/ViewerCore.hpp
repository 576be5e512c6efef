#pragma once
// What the window and the headless viewer share: the newest frame from the link becomes
// instances, plots and counts; the scene, the probe and the panel are drawn into the bound
// framebuffer; pointer input (in NDC, from the window) drives the camera, the mouse probe and
// seeding. The probe goes to the link whenever it changes, the sliders' commands at most every
// 100 ms. Needs a current OpenGL context and an ImGui context with its OpenGL3 backend.
#include "link/ViewerLink.hpp"
#include "render/InstanceRenderer.hpp"
#include "scene/Camera.hpp"
#include "scene/MouseProbe.hpp"
#include "ui/ViewerPanel.hpp"

#include <functional>
#include <memory>

namespace bop::viz {

class ViewerCore {
public:
    explicit ViewerCore(ViewerLink& link);

    // Takes the newest frame if one came since the last call; true when it did.
    bool poll(double nowS);
    // One picture: starts ImGui's frame (`platformFrame` is the platform backend's NewFrame, or
    // sets the display size headless), lays out the panel when `panel`, draws the scene and the
    // probe, then the panel, into the bound framebuffer of width x height pixels.
    void draw(int width, int height, double nowS, bool panel, const std::function<void()>& platformFrame);

    // Pointer input: buttons 0 left, 1 right; positions in NDC of a view of the given aspect.
    void press(int button, double x, double y, double aspect);
    void move(double x, double y, double aspect);
    void release(int button);
    void scroll(double notches);
    void key(char k);  // 'F' fit, 'R' reset, 'P' pause/resume, 'N' single step, 'S' screenshot

    // The probe placed by a script (headless runs): position (length) and on/off.
    void scriptProbe(const Eigen::Vector3d& position, bool active);
    // A blade at `position` (length) of `radius` (length): the path it has gone since the last
    // stroke becomes a Cut once it is a radius long (the first call: a point). Headless scripts and
    // the cut tool's drag.
    void scriptCut(const Eigen::Vector3d& position, double radius);
    // Sets the k0 and k1 sliders (sent as commands too, and with every probe); 0 keeps one.
    void setProbeParameters(double k0, double k1);

    bool takeScreenshotRequest();
    const protocol::StateFrame* frame() const { return frame_.get(); }
    OrbitCamera camera;
    MouseProbe probe;
    PanelState panel;

private:
    void newScene(const protocol::SceneInfo& s);
    void fit(double panelFraction);  // to the particles of the frame; the panel covers panelFraction of the width
    void sendProbe();

    ViewerLink& link_;
    std::shared_ptr<const protocol::SceneInfo> scene_;
    std::uint64_t sceneVersion_ = 0, seenFrames_ = 0;
    std::shared_ptr<const protocol::StateFrame> frame_;
    Controls controls_;
    Instances instances_;
    std::vector<std::size_t> perSpecies_;
    InstanceRenderer renderer_;
    RateMeter received_, drawn_;
    PlotHistory plots_;
    double lastFrameS_ = 0, lastCommandsS_ = 0, aspect_ = 16.0 / 9.0;
    bool fitPending_ = false;
    int dragButton_ = -1;
    double lastX_ = 0, lastY_ = 0;
    std::optional<Eigen::Vector3d> bladeAt_;  // where the cut's last stroke ended (none: not cutting)
};

}  // namespace bop::viz
