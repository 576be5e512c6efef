#include "app/cardiac/CardiacRun.hpp"

#include "bop/common/PythonPlot.hpp"
#include "core/FilledVolume.hpp"

#include <cmath>
#include <ostream>
#include <stdexcept>

namespace bop::app {
namespace {

double mlPerLength3(const GradientMap& map) {
    const double mmPerLength = map.grid.voxelMm / voxelLength(map.r0Voxels);
    return std::pow(mmPerLength, 3) / 1000;
}

std::vector<double> cavityMl(const std::vector<core::MapVolume>& frames, const GradientMap& map) {
    std::vector<double> out;
    for (const core::MapVolume& v : frames) out.push_back(v.bagVoxels * std::pow(map.grid.voxelMm, 3) / 1000);
    return out;
}

}  // namespace

void CardiacRun::record(core::Run& run, const core::Model& model) {
    const core::Totals t = run.totals();
    const long long n = run.stepNumber();
    if (wantsParticles(n)) {
        const core::Particles all = run.gather();
        if (run.rank() == 0) particles(model, all);
    }
    step({n, double(n) * model.integration.dt, t.keyframe, t.bloodMv2, t.virialVolume, t.wallVirial, t.bloodCount,
          t.bloodVolume, t.cavityVolume});
}

CardiacRun::CardiacRun(const Scene& scene, const GradientMap& map, const std::vector<core::MapVolume>& frames)
    : settings_(scene.pressure.value_or(PressureSettings{})),
      dims_(map.wholeDims()),
      h_(voxelLength(map.r0Voxels)),
      mlPerLength3_(mlPerLength3(map)),
      series_(settings_, scene.model->keyframes, mlPerLength3_, cavityMl(frames, map)) {}

double CardiacRun::filledMl(const core::Model& model, const core::Particles& all) const {
    std::vector<Eigen::Vector3d> pos, normal;
    for (std::size_t i = 0; i < all.size(); ++i)
        if (all.species[i] == 1 && model.isSurface(1)) pos.push_back(all.pos[i]), normal.push_back(all.normal[i]);
    return core::filledVoxels(dims_, h_, pos, normal, 1.5 * core::kR0) * h_ * h_ * h_ * mlPerLength3_;
}

void CardiacRun::particles(const core::Model& model, const core::Particles& all) {
    series_.addParticleVolume(filledMl(model, all));
}

void CardiacRun::finish(const std::string& outDir, std::ostream& log) const {
    const std::string csv = outDir + "/pressure.csv";
    series_.writeCsv(csv);
    try {
        const CardiacCycle c = series_.cycle();
        CardiacSeries::writeCycleCsv(outDir + "/pressure-cycle.csv", c);
        CardiacSeries::writeVolumeCycleCsv(outDir + "/volume-cycle.csv", c);
        cycleWritten_ = true;
        log << CardiacSeries::summary(c) << "\npressure: " << csv << ", " << outDir << "/pressure-cycle.csv, " << outDir
            << "/volume-cycle.csv" << std::endl;
    } catch (const std::runtime_error& e) {
        log << "pressure: " << csv << " (no averaged cycle: " << e.what() << ")\n";
    }
}

void CardiacRun::plot(const std::string& outDir, std::ostream& log, bool detached) const {
    if (!cycleWritten_) return;  // no whole cycle: finish() said why
    const std::vector<std::string> files{outDir + "/pressure-cycle.csv", outDir + "/volume-cycle.csv",
                                         outDir + "/pressure.png"};
    if (detached) {
        log << "pressure plot: " << outDir
            << "/pressure.png, drawn in the background by: " << plotWithMatplotlibDetached("pressure", files)
            << std::endl;
        return;
    }
    const std::string why = plotWithMatplotlib("pressure", files);
    log << (why.empty() ? "pressure plot: " + outDir + "/pressure.png" : "no pressure.png: " + why) << std::endl;
}

}  // namespace bop::app
