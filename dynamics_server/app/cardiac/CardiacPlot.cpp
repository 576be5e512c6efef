// The picture of one averaged cycle, laid out like the paper's Figure 12: the blood's pressure
// (spline fit, scaled to the peak in mmHg) over a typical left-ventricular curve, and below it
// the cavity volume from the voxels and from the particles.
#include "app/cardiac/CardiacSeries.hpp"
#include "bop/common/Canvas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bop::app {
namespace {

struct Panel {
    int left, top, width, height;
    double lo, hi;  // value range, bottom to top
    int x(double phase) const { return left + int(std::lround(phase * width)); }
    int y(double v) const { return top + height - int(std::lround((v - lo) / (hi - lo) * height)); }
};

void frame(Canvas& c, const Panel& p, const char* title, const char* unit, double tick) {
    const Rgb axis{60, 60, 60}, grid{225, 225, 225};
    for (double v = std::ceil(p.lo / tick) * tick; v <= p.hi + 1e-9; v += tick) {
        c.drawLine(p.left, p.y(v), p.left + p.width, p.y(v), grid, 1);
        char label[32];
        std::snprintf(label, sizeof label, "%.0f", v);
        c.drawText(p.left - 8 - c.textWidth(label), p.y(v) - 6, label, axis);
    }
    for (int k = 0; k <= 8; ++k) c.drawLine(p.x(k / 8.0), p.top, p.x(k / 8.0), p.top + p.height, grid, 1);
    c.drawLine(p.left, p.top, p.left, p.top + p.height, axis);
    c.drawLine(p.left, p.top + p.height, p.left + p.width, p.top + p.height, axis);
    c.drawText(p.left, p.top - 18, title, axis, 1);
    c.drawText(6, p.top + p.height / 2, unit, axis, 1);
}

void curve(Canvas& c, const Panel& p, const std::vector<double>& x, const std::vector<double>& v, Rgb colour) {
    for (std::size_t k = 1; k < x.size(); ++k)
        c.drawLine(p.x(x[k - 1]), p.y(v[k - 1]), p.x(x[k]), p.y(v[k]), colour, 3);
}

}  // namespace

void CardiacSeries::writePng(const std::string& path, const CardiacCycle& cy) {
    Canvas c(860, 640, {255, 255, 255});
    const Rgb bop{200, 50, 30}, typical{120, 120, 120}, voxels{40, 90, 200}, particles{230, 140, 20}, text{30, 30, 30};
    double low = 0, high = 140;
    for (double v : cy.fitMmHg) low = std::min(low, v), high = std::max(high, v + 10);
    Panel pressure{80, 50, 740, 300, std::floor(low / 20) * 20, std::ceil(high / 20) * 20};
    frame(c, pressure, "Pressure through one cardiac cycle (end-diastole at 0), scaled to the peak", "mmHg", 20);
    curve(c, pressure, cy.fitPhase, cy.typicalMmHg, typical);
    curve(c, pressure, cy.fitPhase, cy.fitMmHg, bop);
    c.fillRect(560, 60, 20, 4, bop);
    c.drawText(586, 55, "bag of particles (spline)", text);
    c.fillRect(560, 78, 20, 4, typical);
    c.drawText(586, 73, "typical left ventricle", text);

    double vmax = 0;
    for (double v : cy.cavityMl) vmax = std::max(vmax, v);
    for (double v : cy.particleMl) vmax = std::max(vmax, v);
    Panel volume{80, 420, 740, 160, 0, std::ceil(vmax / 20) * 20 + 20};
    frame(c, volume, "Cavity volume", "mL", 40);
    curve(c, volume, cy.phase, cy.cavityMl, voxels);
    for (std::size_t k = 0; k < cy.phase.size(); ++k)
        if (cy.particleMl[k] >= 0)
            c.fillRect(volume.x(cy.phase[k]) - 3, volume.y(cy.particleMl[k]) - 3, 7, 7, particles);
    char label[160];
    std::snprintf(label, sizeof label, "voxels (EF %.1f%%)", 100 * cy.efVoxels);
    c.fillRect(560, 430, 20, 4, voxels);
    c.drawText(586, 425, label, text);
    std::snprintf(label, sizeof label, "particles (EF %.1f%%)", 100 * cy.efParticles);
    c.fillRect(566, 446, 7, 7, particles);
    c.drawText(586, 443, label, text);
    c.drawText(80, 600, "phase of the cycle (0 .. 1; frames at every 1/8)", text);
    c.writePng(path);
}

}  // namespace bop::app
