#pragma once
// The two ways bop-viewer runs, sharing ViewerCore: a GLFW window with the panel and pointer
// input, and headless (EGL, no display) writing every new frame as a PNG file.
#include "link/ViewerLink.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace bop::viz {

// A probe moved by a script in a headless run: from `from` to `to` (length) over `seconds` of
// wall time from the first frame, then held there; on throughout.
struct ProbeScript {
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
    double seconds = 1;
    double k0 = 0, k1 = 0;  // range scale and strength (paper eq. 9); 0 = the server's
    double cutRadius = 0;   // above 0: the probe is a blade of this radius (length) and its path cuts
};

struct LoopOptions {
    int frames = 0;                    // new frames to draw, then exit; 0 = until the window closes (window only)
    int width = 960, height = 540;     // pixels
    bool panel = true;                 // draw the ImGui panel
    std::string outDir;                // headless pictures and frames.csv; screenshots of the window
    std::string screenshot;            // also write the last picture here (PNG); empty = no
    std::optional<ProbeScript> probe;  // headless only
    std::vector<std::string> hide;     // bags or species to hide, by name
};

int runHeadless(ViewerLink& link, const LoopOptions& options);  // exit code
int runWindow(ViewerLink& link, const LoopOptions& options);    // exit code; bop::Error without a display

}  // namespace bop::viz
