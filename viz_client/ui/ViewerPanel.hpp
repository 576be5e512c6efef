#pragma once
// The viewer's Dear ImGui panel: connection state and rates, the probe's round trip, the bags
// (colours, particle counts, a switch to hide each), view toggles and the cut plane, the mouse
// tool, the construction menu (species to seed, births on or off), the sliders (sent as commands
// through the link), run control, recording, the live plots and the newest command replies.
// Draws between ImGui::NewFrame and Render.
#include "link/ViewerLink.hpp"
#include "scene/Controls.hpp"
#include "scene/Instances.hpp"
#include "scene/Telemetry.hpp"

#include <string>
#include <vector>

namespace bop::viz {

inline constexpr float kPanelWidthPx = 360;  // the panel's width as it first opens

enum class MouseTool { View = 0, Probe = 1, Seed = 2, Cut = 3 };

// What the panel edits besides the sliders (Controls).
struct PanelState {
    MouseTool tool = MouseTool::View;
    int seedSpecies = 1;        // 1-based
    float bladeR0 = 1;          // the cut tool's blade radius, r0
    std::vector<bool> birthOn;  // by species number; the panel's idea, unknown at connect
    bool paused = false;
    int singleSteps = 1;
    bool recording = false;
    std::string recordName;  // empty: the server's default name
    ViewFilter filter;
    std::vector<std::string> hideAtStart;  // bags or species hidden whenever a scene arrives (--hide)
    bool cutOn = false;
    float cutOffsetR0 = 0;  // the cut plane faces the eye, this far beyond the target, r0
    bool fitRequested = false, resetRequested = false, screenshotRequested = false;
};

// What the panel shows, measured by the caller.
struct PanelFigures {
    const LinkStatus* link = nullptr;
    const protocol::SceneInfo* scene = nullptr;
    const protocol::StateFrame* frame = nullptr;  // the newest drawn
    std::vector<std::size_t> perSpecies;          // particles in the frame by species number
    double receivedHz = 0, drawnHz = 0;           // frames per second
    double frameAgeS = 0;                         // since the newest frame arrived, s
    const PlotHistory* plots = nullptr;
};

// Draws the panel; commands go through `link`.
void drawPanel(PanelState& state, Controls& controls, ViewerLink& link, const PanelFigures& figures);

}  // namespace bop::viz
