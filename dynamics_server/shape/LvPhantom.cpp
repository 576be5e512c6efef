#include "LvPhantom.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace bop::shape {
namespace {

// 0 at s <= 0 to 1 at s >= 1, smooth (half a cosine).
double ramp(double s) {
    s = std::clamp(s, 0.0, 1.0);
    return 0.5 * (1 - std::cos(M_PI * s));
}

// The truncated spheroid's volume is pi a b^2 k with k = (1 + c) - (1 + c^3) / 3.
double shapeFactor(double c) {
    return (1 + c) - (1 + c * c * c) / 3;
}

}  // namespace

double lvVolumeMl(const LvPhantomParams& p, double phase) {
    phase -= std::floor(phase);
    const double ed = p.edvMl, es = p.esvMl, fill = es + 0.7 * (ed - es), late = es + 0.78 * (ed - es);
    if (phase < 0.05) return ed;                                                 // isovolumic contraction
    if (phase < 0.375) return ed - (ed - es) * ramp((phase - 0.05) / 0.325);     // ejection
    if (phase < 0.45) return es;                                                 // isovolumic relaxation
    if (phase < 0.65) return es + (fill - es) * ramp((phase - 0.45) / 0.2);      // rapid filling
    if (phase < 0.85) return fill + (late - fill) * ramp((phase - 0.65) / 0.2);  // diastasis
    return late + (ed - late) * ramp((phase - 0.85) / 0.15);                     // atrial kick
}

double lvTypicalPressureMmHg(double phase) {
    phase -= std::floor(phase);
    if (phase < 0.05) return 10 + 70 * ramp(phase / 0.05);              // isovolumic contraction
    if (phase < 0.18) return 80 + 40 * ramp((phase - 0.05) / 0.13);     // ejection, rising
    if (phase < 0.375) return 120 - 20 * ramp((phase - 0.18) / 0.195);  // ejection, falling
    if (phase < 0.45) return 100 - 95 * ramp((phase - 0.375) / 0.075);  // isovolumic relaxation
    if (phase < 0.85) return 5 + 3 * ramp((phase - 0.45) / 0.4);        // filling
    if (phase < 0.93) return 8 + 4 * ramp((phase - 0.85) / 0.08);       // atrial kick
    return 12 - 2 * ramp((phase - 0.93) / 0.07);
}

LvShape lvShapeFor(const LvPhantomParams& p, double volumeMl) {
    const double k = shapeFactor(p.baseCut), vMm3 = volumeMl * 1000;
    const double aEd = std::cbrt(p.edvMl * 1000 * p.aspectEd * p.aspectEd / (M_PI * k));
    const double phi = (p.edvMl - volumeMl) / (p.edvMl - p.esvMl);  // 0 at end-diastole, 1 at end-systole
    LvShape s;
    s.a = aEd * (1 - p.axialShortening * phi);
    s.b = std::sqrt(vMm3 / (M_PI * k * s.a));
    s.centreZ = s.a;
    s.baseZ = s.a * (1 + p.baseCut);
    s.volumeMl = M_PI * k * s.a * s.b * s.b / 1000;
    return s;
}

double ejectionFraction(const std::vector<double>& v) {
    if (v.empty()) return 0;
    const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *hi > 0 ? (*hi - *lo) / *hi : 0;
}

double LvPhantom::ejectionFraction() const {
    return shape::ejectionFraction(volumeMl);
}
double LvPhantom::voxelEjectionFraction() const {
    return shape::ejectionFraction(voxelVolumeMl);
}

LvPhantom makeLvPhantom(const LvPhantomParams& p) {
    if (!(p.edvMl > p.esvMl && p.esvMl > 0))
        throw std::invalid_argument("LV phantom: expected end-diastolic > end-systolic volume > 0 mL");
    if (p.frames < 2 || !(p.voxelMm > 0) || !(p.aspectEd > 0) || !(p.baseCut > -1 && p.baseCut < 1) ||
        !(p.axialShortening >= 0 && p.axialShortening < 1) || p.marginVoxels < 1)
        throw std::invalid_argument(
            "LV phantom: frames >= 2, voxel size > 0, aspect > 0, base cut in (-1, 1), "
            "shortening in [0, 1) and margin >= 1 expected");
    const LvShape ed = lvShapeFor(p, p.edvMl);
    const double h = p.voxelMm;
    Dims d;
    d.nx = d.ny = int(std::ceil(2 * ed.b / h)) + 2 * p.marginVoxels;
    d.nz = int(std::ceil(ed.baseZ / h)) + 2 * p.marginVoxels;
    // The apex sits margin voxels above the grid's bottom, the axis through the grid's centre.
    const double cx = 0.5 * d.nx * h, cy = 0.5 * d.ny * h, apexZ = p.marginVoxels * h;
    LvPhantom out;
    for (int f = 0; f < p.frames; ++f) {
        const double phase = double(f) / p.frames;
        const LvShape s = lvShapeFor(p, lvVolumeMl(p, phase));
        ScalarImage img;
        img.dims = d;
        img.spacingMm = Eigen::Vector3d::Constant(h);
        img.originMm = Eigen::Vector3d::Zero();
        img.values.assign(d.count(), 0.0f);
        std::size_t inside = 0;
        for (int z = 0; z < d.nz; ++z)
            for (int y = 0; y < d.ny; ++y)
                for (int x = 0; x < d.nx; ++x) {
                    const double px = (x + 0.5) * h - cx, py = (y + 0.5) * h - cy, pz = (z + 0.5) * h - apexZ;
                    const double u = (pz - s.centreZ) / s.a;
                    if (pz > s.baseZ || (px * px + py * py) / (s.b * s.b) + u * u > 1) continue;
                    img.values[d.index(x, y, z)] = 1.0f;
                    ++inside;
                }
        out.frames.push_back(std::move(img));
        out.phase.push_back(phase);
        out.volumeMl.push_back(s.volumeMl);
        out.voxelVolumeMl.push_back(double(inside) * h * h * h / 1000);
    }
    return out;
}

}  // namespace bop::shape
