#include "app/cardiac/CardiacSeries.hpp"

#include "app/cardiac/PeriodicSpline.hpp"
#include "bop/common/Error.hpp"
#include "core/BloodPressure.hpp"
#include "shape/LvPhantom.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace bop::app {

CardiacSeries::CardiacSeries(const PressureSettings& settings, const core::KeyframeSchedule& schedule,
                             double mlPerLength3, std::vector<double> frameCavityMl)
    : settings_(settings), schedule_(schedule), mlPerLength3_(mlPerLength3), frameCavityMl_(std::move(frameCavityMl)) {}

void CardiacSeries::add(const CardiacStep& s) {
    const double v = s.bloodVolume;
    sum_.time += s.time;
    // The keyframe phase, unwrapped against the window's first step (7.9 then 0.1 is 8.1, not a mean of 4).
    double phase = s.keyframe.phase();
    if (inWindow_ == 0) firstPhase_ = phase;
    const double frames = std::max(1, schedule_.frames);
    phase += frames * std::round((firstPhase_ - phase) / frames);
    sum_.frame += phase;
    sum_.cavityMl += s.cavityVolume * mlPerLength3_;
    sum_.bloodMl += v * mlPerLength3_;
    sum_.pressure += core::virialPressure(s.mv2, s.virialVolume, v);
    sum_.pressureEq15 += core::paperEq15Pressure(s.mv2, s.virialVolume, s.count, v);
    sum_.pressureWall += v > 0 ? -s.wallVirial / (3 * v) : 0.0;
    sum_.temperature += s.count > 0 ? s.mv2 / (3 * s.count) : 0.0;
    sum_.particles += s.count;
    if (++inWindow_ < settings_.averageSteps) return;
    const double n = double(inWindow_);
    CardiacRow r;
    r.step = s.step;
    r.frame = std::fmod(sum_.frame / n + frames, frames);
    r.time = sum_.time / n, r.cavityMl = sum_.cavityMl / n, r.bloodMl = sum_.bloodMl / n;
    r.pressure = sum_.pressure / n, r.pressureEq15 = sum_.pressureEq15 / n, r.pressureWall = sum_.pressureWall / n;
    r.temperature = sum_.temperature / n, r.particles = sum_.particles / n;
    r.particleMl = pendingParticleMl_;
    rows_.push_back(r);
    sum_ = CardiacRow{};
    inWindow_ = 0;
    pendingParticleMl_ = -1;
}

void CardiacSeries::addParticleVolume(double ml) {
    pendingParticleMl_ = ml;
}

CardiacCycle CardiacSeries::cycle() const {
    if (!schedule_.animated()) throw std::runtime_error("the pressure cycle needs a keyframed scene ([keyframes])");
    const double period = schedule_.period(), from = schedule_.startTime + settings_.skipCycles * period;
    // Four bins per frame, but no narrower than the rows' spacing (each bin needs rows).
    const double spacing = rows_.size() > 1 ? rows_[1].time - rows_[0].time : period;
    const int bins = std::max(3, std::min(4 * schedule_.frames, int(std::floor(period / spacing + 1e-9))));
    std::vector<double> p(std::size_t(bins), 0), vol(std::size_t(bins), 0), part(std::size_t(bins), 0);
    std::vector<int> n(std::size_t(bins), 0), np(std::size_t(bins), 0);
    double last = from;
    for (const CardiacRow& r : rows_) {
        if (r.time < from) continue;
        // Phase of the cardiac cycle: 0 where frame 0 (end-diastole) comes into force.
        const double phase = (r.time - schedule_.startTime) / period + double(schedule_.firstFrame) / schedule_.frames;
        const std::size_t b = std::size_t(std::min(bins - 1, int((phase - std::floor(phase)) * bins)));
        p[b] += settings_.paperEq15 ? r.pressureEq15 : r.pressure;
        vol[b] += r.cavityMl;
        ++n[b];
        if (r.particleMl >= 0) part[b] += r.particleMl, ++np[b];
        last = r.time;
    }
    const int cycles = int(std::floor((last - from + spacing) / period + 1e-9));  // rows stand for their window
    if (*std::min_element(n.begin(), n.end()) == 0)
        throw std::runtime_error("the pressure cycle needs one whole cycle after the " +
                                 std::to_string(settings_.skipCycles) + " skipped (keyframes start at time " +
                                 std::to_string(schedule_.startTime) + ", period " + std::to_string(period) +
                                 "): run longer");
    CardiacCycle c;
    c.cycles = std::max(1, cycles);
    std::vector<double> particleMeans;
    for (std::size_t b = 0; b < std::size_t(bins); ++b) {
        c.phase.push_back((double(b) + 0.5) / bins);
        c.pressure.push_back(p[b] / n[b]);
        c.cavityMl.push_back(vol[b] / n[b]);
        c.particleMl.push_back(np[b] ? part[b] / np[b] : -1.0);
        if (np[b]) particleMeans.push_back(part[b] / np[b]);
    }
    // The knots sit at bin centres; the spline's own x runs from the first centre.
    const PeriodicSpline spline(c.pressure);
    double peak = -1e300;
    for (int k = 0; k < 400; ++k) {
        const double phase = (k + 0.5) / 400, value = spline(phase - 0.5 / bins);
        c.fitPhase.push_back(phase);
        c.fitMmHg.push_back(value);
        c.typicalMmHg.push_back(shape::lvTypicalPressureMmHg(phase));
        if (value > peak) peak = value, c.peakPhase = phase;
    }
    c.scale = peak > 0 ? settings_.peakMmHg / peak : 0.0;
    for (double& v : c.fitMmHg) v *= c.scale;
    c.minVolumePhase =
        c.phase[std::size_t(std::min_element(c.cavityMl.begin(), c.cavityMl.end()) - c.cavityMl.begin())];
    c.efVoxels = shape::ejectionFraction(frameCavityMl_);
    c.efParticles = shape::ejectionFraction(particleMeans);
    return c;
}

void CardiacSeries::writeCsv(const std::string& path) const {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the pressure series");
    out << "step,time,frame,cavity_ml,blood_volume_ml,particle_volume_ml,pressure,pressure_eq15,pressure_wall,"
           "temperature,blood_particles\n";
    char line[320];
    for (const CardiacRow& r : rows_) {
        char part[32] = "";
        if (r.particleMl >= 0) std::snprintf(part, sizeof part, "%.4f", r.particleMl);
        std::snprintf(line, sizeof line, "%lld,%.4f,%.4f,%.4f,%.4f,%s,%.6g,%.6g,%.6g,%.6g,%.0f\n", r.step, r.time,
                      r.frame, r.cavityMl, r.bloodMl, part, r.pressure, r.pressureEq15, r.pressureWall, r.temperature,
                      r.particles);
        out << line;
    }
    if (!out.flush()) throw Error(path, "cannot write the pressure series");
}

void CardiacSeries::writeCycleCsv(const std::string& path, const CardiacCycle& c) {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the pressure cycle");
    out << "phase,pressure_fit_mmhg,typical_mmhg\n";
    for (std::size_t k = 0; k < c.fitPhase.size(); ++k)
        out << c.fitPhase[k] << ',' << c.fitMmHg[k] << ',' << c.typicalMmHg[k] << '\n';
    if (!out.flush()) throw Error(path, "cannot write the pressure cycle");
}

void CardiacSeries::writeVolumeCycleCsv(const std::string& path, const CardiacCycle& c) {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the volume cycle");
    out << "phase,cavity_ml,particle_ml,ef_voxels,ef_particles\n";
    for (std::size_t k = 0; k < c.phase.size(); ++k)
        out << c.phase[k] << ',' << c.cavityMl[k] << ',' << c.particleMl[k] << ',' << c.efVoxels << ',' << c.efParticles
            << '\n';
    if (!out.flush()) throw Error(path, "cannot write the volume cycle");
}

std::string CardiacSeries::summary(const CardiacCycle& c) {
    char s[400];
    std::snprintf(s, sizeof s,
                  "cycle (mean of %d): pressure peaks at phase %.3f, cavity smallest at phase %.3f; ejection fraction "
                  "%.1f%% from the voxels, %.1f%% from the particles; %.4g mmHg per pressure unit",
                  c.cycles, c.peakPhase, c.minVolumePhase, 100 * c.efVoxels, 100 * c.efParticles, c.scale);
    return s;
}

}  // namespace bop::app
