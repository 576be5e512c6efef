// The beating left ventricle of config/scenes/ventricle.toml (paper §5.2): built at
// end-diastole, then one cycle through the 8 gated frames of the synthetic phantom. The
// ejection fraction from the maps' voxels matches the phantom's ground truth; the blood's
// pressure peaks in systole, within one frame of the smallest cavity; the particles follow the
// wall at end-diastole and eject less than the voxels (the blood has no valve to leave by).
#include "OneProcessRun.hpp"
#include "TestUtil.hpp"
#include "app/cardiac/CardiacRun.hpp"
#include "app/scene/RunStart.hpp"
#include "shape/LvPhantom.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace bop;

TEST_CASE("the ventricle beats: ejection fraction and the pressure peak in systole", "[ventricle]") {
    app::Scene scene = app::loadScene(test::sourceDir() + "/config/scenes/ventricle.toml");
    REQUIRE(scene.pressure);
    scene.pressure->skipCycles = 0;  // construction ends at rest at end-diastole: the first cycle counts
    test::OneProcessRun sim(scene);
    app::CardiacRun cardiac(scene, *sim->mapInForce().map(), sim->frameVolumes());
    const core::KeyframeSchedule& k = scene.model->keyframes;
    const long long start = std::llround(k.startTime / scene.model->integration.dt);
    const long long steps = start + std::llround(k.period() / scene.model->integration.dt);
    double builtMl = 0;
    std::size_t builtSurface = 0, builtVolume = 0;
    for (long long s = 1; s <= steps; ++s) {
        sim->step();
        const core::StepStats& st = sim->stats();
        if (cardiac.wantsParticles(st.step)) cardiac.particles(sim->model(), sim->particles());
        cardiac.step({st.step, st.time, st.keyframe, st.blood.mv2, st.forces.virialVolume, st.forces.wallVirial,
                      st.blood.count, st.bloodVolume, st.cavityVolume});
        if (s == start) {
            builtMl = cardiac.filledMl(sim->model(), sim->particles());
            for (auto sp : sim->particles().species) (sim->model().isSurface(sp) ? builtSurface : builtVolume) += 1;
        }
    }
    const app::CardiacCycle c = cardiac.series().cycle();
    const double truth = shape::makeLvPhantom({}).ejectionFraction();  // the generator's ground truth
    const double cavityEd =
        sim->frameVolumes()[0].bagVoxels * std::pow(sim->mapInForce().map()->grid.voxelMm, 3) / 1000;  // mL
    std::ostringstream what;
    what << "built at end-diastole: " << builtSurface << " surface and " << builtVolume << " volume particles filling "
         << builtMl << " mL of the " << cavityEd << " mL cavity; " << app::CardiacSeries::summary(c) << "; truth EF "
         << truth;
    INFO(what.str());
    WARN(what.str());  // the figures, printed whether or not the checks pass
    CHECK(std::abs(c.efVoxels - truth) < 0.01);
    CHECK(std::abs(c.minVolumePhase - 3.0 / 8) <= 1.0 / 16);  // end-systole, within a bin
    double apart = std::abs(c.peakPhase - c.minVolumePhase);
    apart = std::min(apart, 1 - apart);
    CHECK(apart <= 1.0 / 8);  // within one frame of the smallest cavity
    CHECK(builtMl == Approx(cavityEd).epsilon(0.05));
    CHECK(c.efParticles > 0.3);
    CHECK(c.efParticles < c.efVoxels);
    CHECK(builtSurface > 500);
    CHECK(builtVolume > 1000);
}
