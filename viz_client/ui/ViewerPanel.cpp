#include "ui/ViewerPanel.hpp"

#include "scene/SceneBags.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace bop::viz {
namespace {

bool sliderDouble(const char* label, double* v, double lo, double hi, const char* format = "%.3f") {
    // Clamped also when typed (ctrl+click): the server refuses k0, k1 <= 0 and negative damping.
    return ImGui::SliderScalar(label, ImGuiDataType_Double, v, &lo, &hi, format, ImGuiSliderFlags_AlwaysClamp);
}

std::string speciesLabel(const protocol::SceneInfo& s, int k) {
    const std::size_t i = std::size_t(k - 1);
    return i < s.species.size() ? s.species[i].name : "species " + std::to_string(k);
}

void status(const PanelFigures& f) {
    const LinkStatus& l = *f.link;
    const ImVec4 colour = l.state == LinkState::Connected ? ImVec4(0.4f, 0.9f, 0.4f, 1) : ImVec4(1, 0.6f, 0.3f, 1);
    ImGui::TextColored(colour, "%s", linkStateName(l.state));
    ImGui::SameLine();
    ImGui::TextWrapped("%s", l.message.c_str());
    if (l.state != LinkState::Connected && l.attempt > 0) ImGui::Text("attempt %d", l.attempt + 1);
    if (f.frame && f.scene && f.scene->unitSystem.physical) {  // a scene with materials: s and N
        const UnitSystem& u = f.scene->unitSystem;
        ImGui::Text("step %llu, t = %.3f s", (unsigned long long)f.frame->step, u.toS(f.frame->simTime));
        ImGui::Text("server %.1f steps/s, real-time factor %.3g", f.frame->stats.stepRateHz,
                    f.frame->stats.realTimeFactor);
        if (f.frame->probeActive) ImGui::Text("probe force %.4g N", u.toN(f.frame->probeForce.norm()));
    } else if (f.frame) {
        ImGui::Text("step %llu, t = %.2f (simulation time)", (unsigned long long)f.frame->step, f.frame->simTime);
        ImGui::Text("server %.1f steps/s", f.frame->stats.stepRateHz);
    }
    ImGui::Text("frames: %.1f/s received, %.1f/s drawn", f.receivedHz, f.drawnHz);
    ImGui::Text("frame age %.0f ms; %llu lost", 1000 * f.frameAgeS,
                (unsigned long long)(l.client.framesLost + l.client.udpFramesLost));
    if (f.frame && f.frame->stats.haptic.rateHz > 0) {
        const protocol::LoopStats& h = f.frame->stats.haptic;
        ImGui::Text("haptic loop %.0f Hz, period error p99 %.0f us, %llu missed", h.rateHz, h.periodErrorP99Us,
                    (unsigned long long)h.missedDeadlines);
    }
    if (l.rttCount > 0)
        ImGui::Text("probe round trip %.1f ms (p50 %.1f, p99 %.1f)", l.rttLastMs, l.rttP50Ms, l.rttP99Ms);
    else
        ImGui::TextDisabled("probe round trip: no probe yet");
}

// One row per bag: its colours, a switch that shows or hides it, and its particles by species
// (surface + volume; a species alone, its count).
void bags(PanelState& s, const PanelFigures& f) {
    const std::vector<BagEntry> list = bagsOfScene(*f.scene);
    s.filter.hiddenSpecies.resize(f.scene->species.size() + 1, false);
    ImGui::TextDisabled("colours, shown, bag");
    ImGui::SameLine(150);
    ImGui::TextDisabled("surface + volume particles");
    for (std::size_t b = 0; b < list.size(); ++b) {
        const BagEntry& bag = list[b];
        ImGui::PushID(int(b));
        for (int sp : bag.species) {
            const auto& c = f.scene->species[std::size_t(sp - 1)].rgba;
            ImGui::ColorButton("##colour", ImVec4(c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, 1),
                               ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoAlpha, ImVec2(12, 12));
            ImGui::SameLine(0, 2);
        }
        bool shown = !bagHidden(s.filter, bag);
        if (ImGui::Checkbox(bag.name.c_str(), &shown)) setBagHidden(s.filter, bag, !shown);
        ImGui::SameLine(150);
        std::string counts;
        for (int sp : bag.species)
            counts += (counts.empty() ? "" : " + ") +
                      std::to_string(std::size_t(sp) < f.perSpecies.size() ? f.perSpecies[std::size_t(sp)] : 0);
        ImGui::TextUnformatted(counts.c_str());
        ImGui::PopID();
    }
}

void view(PanelState& s) {
    ImGui::Checkbox("surface", &s.filter.showSurface);
    ImGui::SameLine();
    ImGui::Checkbox("volume", &s.filter.showVolume);
    ImGui::Checkbox("cut plane", &s.cutOn);
    if (s.cutOn) ImGui::SliderFloat("cut offset, r0", &s.cutOffsetR0, -20, 20);
    s.fitRequested = ImGui::Button("fit (F)") || s.fitRequested;
    ImGui::SameLine();
    s.resetRequested = ImGui::Button("reset (R)") || s.resetRequested;
    ImGui::SameLine();
    s.screenshotRequested = s.screenshotRequested || ImGui::Button("screenshot (S)");
    int tool = int(s.tool);
    ImGui::Text("mouse:");
    ImGui::SameLine();
    ImGui::RadioButton("view", &tool, int(MouseTool::View));
    ImGui::SameLine();
    ImGui::RadioButton("probe", &tool, int(MouseTool::Probe));
    ImGui::SameLine();
    ImGui::RadioButton("seed", &tool, int(MouseTool::Seed));
    ImGui::SameLine();
    ImGui::RadioButton("cut", &tool, int(MouseTool::Cut));
    s.tool = MouseTool(tool);
    if (s.tool == MouseTool::Cut)  // a drag across the view plane through the target cuts the bags
        ImGui::SliderFloat("blade radius, r0", &s.bladeR0, 0.5f, 4.0f, "%.2f");
}

void construction(PanelState& s, ViewerLink& link, const protocol::SceneInfo& scene) {
    const int n = int(scene.species.size());
    s.birthOn.resize(std::size_t(n) + 1, false);
    s.seedSpecies = std::clamp(s.seedSpecies, 1, std::max(1, n));
    if (ImGui::BeginCombo("seed species", speciesLabel(scene, s.seedSpecies).c_str())) {
        for (int k = 1; k <= n; ++k)
            if (ImGui::Selectable(speciesLabel(scene, k).c_str(), k == s.seedSpecies)) s.seedSpecies = k;
        ImGui::EndCombo();
    }
    ImGui::TextDisabled("seed tool: click in the scene to seed at the 3D cursor");
    for (int k = 1; k <= n; ++k) {
        bool on = s.birthOn[std::size_t(k)];
        if (ImGui::Checkbox(("births of " + speciesLabel(scene, k)).c_str(), &on)) {
            s.birthOn[std::size_t(k)] = on;
            link.submit(birthCommand(k, on));
        }
    }
}

void run(PanelState& s, ViewerLink& link) {
    if (ImGui::Button(s.paused ? "resume (P)" : "pause (P)")) {
        s.paused = !s.paused;
        link.submit(runCommand(s.paused ? protocol::RunAction::Pause : protocol::RunAction::Resume));
    }
    ImGui::SameLine();
    ImGui::BeginDisabled(!s.paused);
    if (ImGui::Button("step (N)"))
        link.submit(runCommand(protocol::RunAction::SingleStep, std::uint32_t(s.singleSteps)));
    ImGui::SameLine();
    ImGui::SetNextItemWidth(90);
    ImGui::InputInt("steps", &s.singleSteps);
    s.singleSteps = std::clamp(s.singleSteps, 1, 100000);
    ImGui::EndDisabled();
    char name[128];
    std::snprintf(name, sizeof name, "%s", s.recordName.c_str());
    ImGui::SetNextItemWidth(160);
    if (ImGui::InputTextWithHint("##record", "file on the server", name, sizeof name)) s.recordName = name;
    ImGui::SameLine();
    if (ImGui::Button(s.recording ? "stop recording" : "record")) {
        s.recording = !s.recording;
        link.submit(recordCommand(s.recording, s.recordName));
    }
}

void tune(Controls& c, const protocol::SceneInfo& scene) {
    const int n = c.species();
    static const char* const tables[] = {"LJ", "co-normal", "co-planar"};
    std::vector<double>* const matrices[] = {&c.now.lj, &c.now.coNormal, &c.now.coPlanar};
    for (int t = 0; t < 3; ++t)
        for (int a = 1; a <= n; ++a)
            for (int b = 1; b <= n; ++b) {
                const std::string label =
                    std::string(tables[t]) + " " + speciesLabel(scene, a) + " <- " + speciesLabel(scene, b);
                sliderDouble(label.c_str(), &(*matrices[t])[std::size_t((a - 1) * n + (b - 1))], 0, 5);
            }
    for (int a = 1; a <= n; ++a) {
        sliderDouble(("drag v " + speciesLabel(scene, a) + ", mass/time").c_str(), &c.now.dragV[std::size_t(a - 1)], 0,
                     10);
        sliderDouble(("drag w " + speciesLabel(scene, a) + ", inertia/time").c_str(), &c.now.dragW[std::size_t(a - 1)],
                     0, 10);
    }
    sliderDouble("probe k0 (range)", &c.now.k0, 0.2, 5);
    sliderDouble("probe k1 (strength)", &c.now.k1, 0.05, 20);
}

void plot(const PlotHistory& h, double PlotSample::*member, const char* label) {
    const std::vector<float> v = h.series(member);
    char overlay[64];
    std::snprintf(overlay, sizeof overlay, "%.4g", v.empty() ? 0.0 : double(v.back()));
    ImGui::PlotLines(label, v.data(), int(v.size()), 0, overlay, FLT_MAX, FLT_MAX, ImVec2(0, 60));
}

}  // namespace

void drawPanel(PanelState& s, Controls& controls, ViewerLink& link, const PanelFigures& f) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(kPanelWidthPx, 0), ImGuiCond_FirstUseEver);
    ImGui::Begin("BoP viewer");
    status(f);
    if (f.scene && ImGui::CollapsingHeader("bags", ImGuiTreeNodeFlags_DefaultOpen)) bags(s, f);
    if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) view(s);
    if (f.scene && ImGui::CollapsingHeader("construction")) construction(s, link, *f.scene);
    if (ImGui::CollapsingHeader("run", ImGuiTreeNodeFlags_DefaultOpen)) run(s, link);
    if (f.scene && ImGui::CollapsingHeader("parameters")) tune(controls, *f.scene);
    if (f.plots && ImGui::CollapsingHeader("plots", ImGuiTreeNodeFlags_DefaultOpen)) {
        // Against simulation time, the newest on the right; simulation units.
        plot(*f.plots, &PlotSample::energy, "energy");
        plot(*f.plots, &PlotSample::pressure, "pressure");
        plot(*f.plots, &PlotSample::probeForce, "probe force");
        if (f.frame && f.frame->stats.cavityVolume > 0) {  // a bag: its volume (a keyframed one beats)
            plot(*f.plots, &PlotSample::cavityVolume, "cavity volume");
            ImGui::Text("map frame %.2f", f.frame->stats.mapFrame);
        }
    }
    for (const std::string& r : f.link->replies) ImGui::TextDisabled("%s", r.c_str());
    ImGui::End();
}

}  // namespace bop::viz
