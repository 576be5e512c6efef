#pragma once
// A run's side of the ventricle measurements ([pressure] in the scene): feeds every step's
// reductions and, every volume_every_steps, the particles to a CardiacSeries, and writes its
// files at the end. Used by the batch and served runs alike.
#include "app/cardiac/CardiacSeries.hpp"
#include "core/Model.hpp"
#include "core/Particles.hpp"
#include "core/Run.hpp"

#include <iosfwd>
#include <string>

namespace bop::app {

class CardiacRun {
public:
    // map: the whole map's header (grid, r0); frames: voxel counts of every keyframe (or the one map).
    CardiacRun(const Scene& scene, const GradientMap& map, const std::vector<core::MapVolume>& frames);

    bool wantsParticles(long long step) const { return step % settings_.volumeEverySteps == 0; }
    void step(const CardiacStep& s) { series_.add(s); }
    // The measurements after a step of `run` (collective: the reductions every step, the
    // particles gathered every volume_every_steps; the series is kept on rank 0).
    void record(core::Run& run, const core::Model& model);
    // Every particle of the run (the outer bag's surface species is used).
    void particles(const core::Model& model, const core::Particles& all);
    // pressure.csv, pressure-cycle.csv and volume-cycle.csv in outDir; a summary on `log`. A run
    // too short for a whole cycle writes the series and says why there is no cycle.
    void finish(const std::string& outDir, std::ostream& log) const;
    // pressure.png from the cycle files (matplotlib, a second or two): called last, after the run
    // has said everything else. detached: drawn by a process nobody waits for (a served run
    // stopped by a signal: mpirun kills its ranks a second after forwarding it).
    void plot(const std::string& outDir, std::ostream& log, bool detached = false) const;

    const CardiacSeries& series() const { return series_; }
    double filledMl(const core::Model& model, const core::Particles& all) const;  // now, mL

private:
    mutable bool cycleWritten_ = false;  // finish() wrote the cycle files plot() draws
    PressureSettings settings_;
    Dims dims_;
    double h_ = 1, mlPerLength3_ = 1;
    CardiacSeries series_;
};

}  // namespace bop::app
