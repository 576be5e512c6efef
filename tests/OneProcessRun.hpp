#pragma once
// A scene's run at one process, started as bop-server starts one (app::startRun, then core::Run
// over core::oneProcess()), its gradient map built into a cache file of its own that goes with it.
// sim-> reaches the run's Simulation between steps.
#include "TestUtil.hpp"
#include "app/scene/RunStart.hpp"
#include "core/Run.hpp"

#include <memory>
#include <optional>
#include <string>

namespace bop::test {

class OneProcessRun {
public:
    // restart: an extended XYZ file to start from ("" = the scene's own start); settle: at the
    // scene's settle time step, as bop-server's batch run settles a placed bag.
    explicit OneProcessRun(const app::Scene& scene, const std::string& restart = "", bool settle = false)
        : dir_(std::make_unique<TempDir>("one-process-run")) {
        app::RunStart s = app::startRun(scene, dir_->file("map.bopgm"), restart, true, [] {});
        if (settle) app::useSettleTimeStep(scene, s);
        map_ = s.options.map;
        timeline_ = s.timeline;
        model_ = s.model;
        run_ = std::make_unique<core::Run>(s.model, s.particles, std::move(s.options));
        run_->setProbe(s.probe);
    }
    core::Simulation* operator->() { return &run_->simulation(); }
    core::Simulation& operator*() { return run_->simulation(); }
    core::Run& run() { return *run_; }
    const std::shared_ptr<const core::Model>& model() const { return model_; }          // the start's: the box placed
    const std::vector<core::ConstructionEvent>& timeline() const { return timeline_; }  // the start's
    // Where the run reads its map windows (for another run of the same scene; none without a map).
    const std::optional<core::MapSource>& mapSource() const { return map_; }
    // The whole map of keyframe `frame`, read from the cache (tests that compare windows with it).
    GradientMap wholeMap(int frame = 0) const {
        const Dims d = map_->header.wholeDims();
        return map_->crop(frame, bop::VoxelWindow{Eigen::Vector3i::Zero(), Eigen::Vector3i(d.nx, d.ny, d.nz)});
    }

private:
    std::unique_ptr<TempDir> dir_;  // the cache; outlives nothing it serves (declared first, dies last)
    std::optional<core::MapSource> map_;
    std::vector<core::ConstructionEvent> timeline_;
    std::shared_ptr<const core::Model> model_;
    std::unique_ptr<core::Run> run_;
};

}  // namespace bop::test
