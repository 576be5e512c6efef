// PNG slice pictures of gradient maps: per plane a labels panel, a signed-distance panel and a
// co-planar weight panel, each with its legend.
#include "app/tools/ShapeReport.hpp"
#include "bop/common/BagColours.hpp"
#include "bop/common/Canvas.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace bop::app {
namespace {

constexpr Rgb kBackground{255, 255, 255}, kInk{20, 20, 20}, kOutside{60, 60, 68};

Rgb speciesColour(int species) {  // the viewer's default colours
    if (species == 0) return kOutside;
    const std::array<float, 3> c = defaultSpeciesColour(species);
    return {std::uint8_t(255 * c[0] + 0.5f), std::uint8_t(255 * c[1] + 0.5f), std::uint8_t(255 * c[2] + 0.5f)};
}

struct Plane {
    const char* name;  // "xy", "xz", "yz"
    int u, v, w;       // axes drawn right, drawn up, and held fixed
};
constexpr Plane kPlanes[] = {{"xy", 0, 1, 2}, {"xz", 0, 2, 1}, {"yz", 1, 2, 0}};

std::string fmt(double x, int digits = 1) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(digits) << x;
    return os.str();
}

// Draws one panel of size (nu*s) x (nv*s) at (x0, y0); colourOf(voxel index) gives the colour.
template <class ColourOf>
void drawPanel(Canvas& c, int x0, int y0, const Dims& d, const Plane& p, int slice, int s, ColourOf colourOf) {
    const int n[3] = {d.nx, d.ny, d.nz};
    for (int b = 0; b < n[p.v]; ++b)
        for (int a = 0; a < n[p.u]; ++a) {
            int ijk[3];
            ijk[p.u] = a;
            ijk[p.v] = b;
            ijk[p.w] = slice;
            const Rgb col = colourOf(d.index(ijk[0], ijk[1], ijk[2]));
            c.fillRect(x0 + a * s, y0 + (n[p.v] - 1 - b) * s, s, s, col);  // v axis points up
        }
}

void colourBar(Canvas& c, int x, int y, int w, const std::string& lo, const std::string& hi, const std::string& title,
               Rgb (*map)(double), double t0, double t1) {
    c.drawText(x, y, title, kInk);
    for (int i = 0; i < w; ++i) c.fillRect(x + i, y + 14, 1, 12, map(t0 + (t1 - t0) * i / double(w - 1)));
    c.drawText(x, y + 30, lo, kInk);
    c.drawText(x + w - c.textWidth(hi), y + 30, hi, kInk);
}

}  // namespace

std::vector<std::string> writeSlicePictures(const std::string& dir, const shape::ShapeBuild& build,
                                            const std::vector<std::string>& bagNames) {
    std::vector<std::string> files;
    std::filesystem::create_directories(dir);
    for (std::size_t f = 0; f < build.frames.size(); ++f) {
        const GradientMap& m = build.frames[f];
        const Dims& d = m.dims();
        const int n[3] = {d.nx, d.ny, d.nz};
        double dmax = 1;
        for (std::size_t v = 0; v < d.count(); ++v) dmax = std::max(dmax, std::abs(m.signedDistance(v)));
        std::vector<int> species;
        for (std::size_t v = 0; v < d.count(); ++v)
            if (std::find(species.begin(), species.end(), m.occ[v]) == species.end()) species.push_back(m.occ[v]);
        std::sort(species.begin(), species.end());

        for (const Plane& p : kPlanes) {
            const int slice = n[p.w] / 2;
            const int s = std::max(1, 360 / std::max(n[p.u], n[p.v]));
            const int pw = n[p.u] * s, ph = n[p.v] * s, gap = 20, legendH = 30 + 14 * int(species.size());
            const int width = 3 * pw + 4 * gap, height = ph + legendH + 3 * gap + 14;
            Canvas c(std::max(width, 420), height, kBackground);
            const char axes[] = "xyz";
            std::ostringstream title;
            title << "frame " << f << ", " << p.name << " plane at " << axes[p.w] << " = " << slice << " voxels ("
                  << n[0] << " x " << n[1] << " x " << n[2] << ", " << m.grid.voxelMm << " mm)";
            c.drawText(gap, 6, title.str(), kInk);
            const int top = gap + 10;
            drawPanel(c, gap, top, d, p, slice, s, [&](std::size_t v) { return speciesColour(m.occ[v]); });
            drawPanel(c, 2 * gap + pw, top, d, p, slice, s,
                      [&](std::size_t v) { return divergingMap(m.signedDistance(v) / dmax); });
            drawPanel(c, 3 * gap + 2 * pw, top, d, p, slice, s, [&](std::size_t v) {
                return m.occ[v] && isSurfaceSpecies(m.occ[v]) ? colourMap(m.nearestSurface(v).cpWeight) : kOutside;
            });
            int y = top + ph + gap;
            c.drawText(gap, y, "labels", kInk);
            for (std::size_t i = 0; i < species.size(); ++i) {
                const int sp = species[i];
                c.fillRect(gap, y + 16 + 14 * int(i), 10, 10, speciesColour(sp));
                std::ostringstream what;
                what << (sp == 0 ? "outside" : (isSurfaceSpecies(sp) ? "surface" : "inside"));
                if (sp) what << " species " << sp;
                const std::size_t bag = std::size_t(bagOfSpecies(sp));
                if (sp && bag <= bagNames.size()) what << " ('" << bagNames[bag - 1] << "')";
                c.drawText(gap + 14, y + 15 + 14 * int(i), what.str(), kInk);
            }
            const int bw = std::min(pw, 200);
            const std::string range = fmt(dmax * m.grid.voxelMm);
            std::ostringstream lo, hi;
            lo << "-" << range << " mm";
            hi << "+" << range << " mm";
            colourBar(c, 2 * gap + pw, y, bw, lo.str(), hi.str(), "distance to nearest surface (inside -, outside +)",
                      divergingMap, -1, 1);
            colourBar(c, 3 * gap + 2 * pw, y, bw, "0", "1", "co-planar weight (surface voxels)", colourMap, 0, 1);
            std::ostringstream name;
            name << dir << "/";
            if (build.frames.size() > 1) name << "frame" << std::setw(2) << std::setfill('0') << f << "-";
            name << "slice-" << p.name << ".png";
            c.writePng(name.str());
            files.push_back(name.str());
        }
    }
    return files;
}

}  // namespace bop::app
