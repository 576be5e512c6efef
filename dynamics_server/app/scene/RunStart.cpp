#include "app/scene/RunStart.hpp"

#include "app/files/ExtendedXyz.hpp"
#include "app/scene/PieceSeeds.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "core/SoundState.hpp"
#include "shape/GradientMapFileView.hpp"
#include "shape/Thickness.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace bop::app {

std::vector<std::string> speciesNames(const core::Model& model) {
    std::vector<std::string> names;
    for (const auto& s : model.species) names.push_back(s.name);
    return names;
}

namespace {

// The box around a map of `dims` voxels, and the probe's start in simulation units.
void placeInMap(const Scene& scene, const GradientMap& map, RunStart& s) {
    const Dims& d = map.wholeDims();
    const double h = voxelLength(map.r0Voxels);
    auto model = std::make_shared<core::Model>(*scene.model);
    model->box.lo.setZero();
    model->box.hi = Eigen::Vector3d(d.nx, d.ny, d.nz) * h;
    s.model = std::move(model);
    if (scene.probePositionVoxels) s.probe.position = *scene.probePositionVoxels * h;
}

}  // namespace

core::Particles initialParticles(const Scene& scene, const core::Model& model,
                                 const std::vector<core::ConstructionEvent>& timeline, const std::string& restart,
                                 long long& firstStep, core::Construction& construction, std::string& settle) {
    firstStep = 0;
    settle.clear();
    construction = core::Construction(scene.construction, timeline, model.speciesCount());
    if (!restart.empty()) {
        XyzFrame f = readExtendedXyz(restart, speciesNames(model));
        // A state a run can start from: finite, near the box, not flung (core/SoundState.hpp).
        if (const core::Unsoundness u = core::findUnsound(model, f.particles, Eigen::Vector3d::Zero()); u.what)
            throw Error(restart, "not a state a run can start from: " + u.text());
        firstStep = f.info.step;
        settle = f.info.settle;
        if (!f.info.births.empty()) {
            try {
                construction.restore(f.info.births, std::uint64_t(std::max(0LL, f.info.seeds)),
                                     std::uint64_t(f.info.nextId));
            } catch (const std::invalid_argument& e) {
                throw Error(restart, e.what());
            }
        }
        return std::move(f.particles);
    }
    return scene.bulk ? bulkLattice(scene) : core::Particles{};
}

RunStart startRun(const Scene& scene, const std::string& cache, const std::string& restart, bool root,
                  const std::function<void()>& waitForAll, const shape::ProgressFn& progress) {
    RunStart s;
    s.model = scene.model;
    s.timeline = scene.timeline;
    s.probe = scene.probe;
    if (scene.shape) {
        if (cache.empty()) throw Error("--cache", "a run on several ranks reads the gradient map from its cache file");
        const std::uint64_t key = bop::hashText(scene.shape->canonical);
        if (root && !shape::GradientMapFileView::open(cache, key))
            shape::loadOrBuildShape(*scene.shape, cache, true, progress);  // builds and writes; the map is let go
        else if (root && progress)
            progress("the gradient map is in the cache " + cache + " (each process reads its window)");
        waitForAll();
        auto view = shape::GradientMapFileView::open(cache, key);
        if (!view)
            throw Error(cache,
                        "gradient-map cache not found by this rank: put --cache on a filesystem every rank sees");
        auto shared = std::make_shared<const shape::GradientMapFileView>(std::move(*view));
        placeInMap(scene, shared->header(0), s);
        // Every frame when the scene cycles them (keyframes), else the first.
        const int frames = scene.model->keyframes.animated() ? shared->frames() : 1;
        s.options.map = core::MapSource{
            shared->header(0), [shared](int f, const bop::VoxelWindow& w) { return shared->crop(f, w); }, frames};
    }
    // A bag to build (not one a restart brings): its thin parts said first, then placed if the
    // scene places it, or seeded in every piece if it grows from seeds.
    const bool place = scene.placement && restart.empty(), warn = root && progress && restart.empty();
    if (scene.shape && (place || warn || hasDefaultSeed(scene.timeline))) {
        const GradientMap header = s.options.map->header;
        const GradientMap whole = s.options.map->crop(
            0, bop::VoxelWindow{Eigen::Vector3i::Zero(),
                                Eigen::Vector3i(header.wholeDims().nx, header.wholeDims().ny, header.wholeDims().nz)});
        // The thin parts: said, and held as membranes where the bag is placed (one search for both).
        std::vector<char> membrane;
        if (warn || place) {
            const std::vector<std::string> thin =
                shape::thinPartsWarnings(whole, scene.shape->bagNames(), place ? &membrane : nullptr);
            if (warn)
                for (const std::string& w : thin) progress("warning: " + w);
        }
        PieceSeeding seeding = seedEveryPiece(*s.model, whole, scene.construction, s.timeline);
        s.timeline = std::move(seeding.timeline);  // every process alike, from the same map
        if (warn && !place)
            for (const std::string& n : seeding.notes) progress(n);
        if (place) {  // every process places on the whole map alike and keeps what it owns (core::Run)
            app::PlacementParams params = *scene.placement;
            params.membrane = &membrane;
            app::Placement placed = app::placeParticles(*s.model, whole, params);
            if (root && progress) progress(placementReport(*s.model, placed.species));
            s.particles = std::move(placed.particles);
        }
    }
    core::Construction construction({}, {}, s.model->speciesCount());
    core::Particles fromFile =
        initialParticles(scene, *s.model, s.timeline, restart, s.firstStep, construction, s.settle);
    s.settleFile = restart;
    if (!place) s.particles = std::move(fromFile);
    s.options.firstStep = s.firstStep;
    s.options.params = scene.params;
    s.options.params->probe = s.probe;
    s.options.construction = std::move(construction);
    return s;
}

void useSettleTimeStep(const Scene& scene, RunStart& start) {
    if (!scene.run.untilSettled) return;
    auto model = std::make_shared<core::Model>(*start.model);
    model->integration.dt = scene.run.settleTimeStep;
    start.model = std::move(model);
}

std::string placementReport(const core::Model& model, const std::vector<app::PlacedSpecies>& placed) {
    std::ostringstream out;
    out << "placed on the map:";
    for (const auto& p : placed)
        out << (&p == placed.data() ? " " : "; ") << model.species[std::size_t(p.species)].name << " " << p.placed
            << " (" << std::fixed << std::setprecision(2) << double(p.placed) / std::max(1.0, p.ideal)
            << std::defaultfloat << " of the " << std::llround(p.ideal) << " at r0 spacing)";
    return out.str();
}

}  // namespace bop::app
