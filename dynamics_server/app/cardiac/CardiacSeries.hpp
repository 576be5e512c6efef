#pragma once
// The ventricle's measurements through its cycles (paper §5.2, Fig. 12): the blood's virial
// pressure (core/BloodPressure.hpp) averaged over `average_steps`, the cavity volume of the
// map(s) in force and of the particles, and at the end one cycle averaged by phase, fitted with
// a periodic cubic spline and scaled to the peak in mmHg, beside a typical left-ventricular
// pressure curve; ejection fractions from the voxels and from the particles.
#include "app/scene/SceneConfig.hpp"
#include "core/Keyframes.hpp"

#include <string>
#include <vector>

namespace bop::app {

struct CardiacStep {  // one step's reductions (the same at every rank count)
    long long step = 0;
    double time = 0;  // simulation time units
    core::KeyframeAt keyframe;
    double mv2 = 0, virialVolume = 0, wallVirial = 0, count = 0;  // energy, energy, energy, particles
    double bloodVolume = 0, cavityVolume = 0;                     // length^3
};

struct CardiacRow {                                           // the mean over one averaging window
    long long step = 0;                                       // last step of the window
    double time = 0, frame = 0;                               // mean time, mean keyframe phase (frame + blend)
    double cavityMl = 0, bloodMl = 0;                         // voxel volumes of the map(s) in force, mL
    double particleMl = -1;                                   // particle-filled volume in this window, mL (-1: none)
    double pressure = 0, pressureEq15 = 0, pressureWall = 0;  // standard, paper eq. 15, wall virial; energy / length^3
    double temperature = 0, particles = 0;                    // sum m v^2 / (3 N), energy; blood particles
};

struct CardiacCycle {                                           // one cycle averaged by phase (bins of equal width)
    std::vector<double> phase, pressure, cavityMl, particleMl;  // particleMl < 0 where no sample fell
    std::vector<double> fitPhase, fitMmHg, typicalMmHg;         // the scaled spline and the reference, 400 points
    double scale = 0;                      // mmHg per pressure unit (peak / the spline's maximum); 0 if it has none
    double peakPhase = 0;                  // where the fitted pressure peaks, cycles
    double minVolumePhase = 0;             // where the voxel cavity is smallest, cycles
    double efVoxels = 0, efParticles = 0;  // ejection fractions, fractions
    int cycles = 0;                        // cycles averaged
};

class CardiacSeries {
public:
    // mlPerLength3: mL per simulation length^3; frameCavityMl: every keyframe's cavity, mL.
    CardiacSeries(const PressureSettings& settings, const core::KeyframeSchedule& schedule, double mlPerLength3,
                  std::vector<double> frameCavityMl);

    void add(const CardiacStep& s);
    void addParticleVolume(double ml);  // measured now: belongs to the current window
    const std::vector<CardiacRow>& rows() const { return rows_; }

    // Needs a keyframed scene and every phase bin filled by cycles after skip_cycles;
    // std::runtime_error otherwise, saying how many more steps are needed.
    CardiacCycle cycle() const;

    void writeCsv(const std::string& path) const;  // every row
    static void writeCycleCsv(const std::string& path, const CardiacCycle& c);
    // phase, cavity_ml (voxels), particle_ml (-1 where not measured), and the cycle's ejection
    // fractions from the voxels and the particles (the same in every row): pressure.png's volume panel
    static void writeVolumeCycleCsv(const std::string& path, const CardiacCycle& c);
    static std::string summary(const CardiacCycle& c);

private:
    PressureSettings settings_;
    core::KeyframeSchedule schedule_;
    double mlPerLength3_;
    std::vector<double> frameCavityMl_;
    std::vector<CardiacRow> rows_;
    CardiacRow sum_;
    long long inWindow_ = 0;
    double firstPhase_ = 0;  // keyframe phase of the window's first step
    double pendingParticleMl_ = -1;
};

}  // namespace bop::app
