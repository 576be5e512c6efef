#include "app/scene/RunStart.hpp"

#include "app/files/ExtendedXyz.hpp"
#include "app/scene/PieceSeeds.hpp"
#include "bop/common/Error.hpp"
#include "bop/common/GradientMapFile.hpp"
#include "core/Bonds.hpp"
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

// A restart file of a bonded bag holds the scene's placed particles (some may have died): each id
// of the file names a placed particle of the same species. After a cut (`cut`), particles born on
// the cut faces (ids beyond the placement's) and volume particles made surface particles of their
// own bag are the run's own too.
void checkPlacedIds(const core::Particles& placed, const core::Particles& file, const core::Model& model,
                    const std::string& restart, bool cut) {
    std::vector<int> speciesOf;
    for (std::size_t i = 0; i < placed.size(); ++i) {
        if (placed.id[i] >= speciesOf.size()) speciesOf.resize(placed.id[i] + 1, 0);
        speciesOf[placed.id[i]] = placed.species[i];
    }
    for (std::size_t i = 0; i < file.size(); ++i) {
        const bool placedId = file.id[i] < speciesOf.size();
        const int was = placedId ? speciesOf[file.id[i]] : 0, is = file.species[i];
        const bool ok = placedId ? was == is || (cut && was > 0 && bagOfSpecies(was) == bagOfSpecies(is)) : cut;
        if (!ok)
            throw Error(restart, "particle id " + std::to_string(file.id[i]) + " (" + model.species[is].name +
                                     ") is not one this scene places: a bonded bag restarts from its own "
                                     "scene's run");
    }
}

std::string bondReport(const core::BondNetwork& net, std::size_t particles) {
    std::ostringstream out;
    out << "bonded: " << net.bonds() << " bonds among " << particles << " placed particles (" << std::fixed
        << std::setprecision(1) << 2.0 * double(net.bonds()) / double(std::max<std::size_t>(1, particles))
        << " a particle), letting go beyond " << std::setprecision(2) << net.cut / kR0 << " r0";
    std::size_t anchored = 0;
    for (double k : net.anchorStiffness) anchored += k > 0;
    if (anchored > 0) out << "; " << anchored << " anchored by the support";
    return out.str();
}

}  // namespace

core::Particles initialParticles(const Scene& scene, const core::Model& model,
                                 const std::vector<core::ConstructionEvent>& timeline, const std::string& restart,
                                 long long& firstStep, core::Construction& construction, std::string& settle,
                                 std::vector<core::CutCommand>& cuts, std::vector<std::vector<std::uint64_t>>& yields) {
    firstStep = 0;
    settle.clear();
    cuts.clear();
    yields.clear();
    construction = core::Construction(scene.construction, timeline, model.speciesCount());
    if (!restart.empty()) {
        XyzFrame f = readExtendedXyz(restart, speciesNames(model));
        // A state a run can start from: finite, near the box, not flung (core/SoundState.hpp).
        if (const core::Unsoundness u = core::findUnsound(model, f.particles, Eigen::Vector3d::Zero()); u.what)
            throw Error(restart, "not a state a run can start from: " + u.text());
        firstStep = f.info.step;
        settle = f.info.settle;
        cuts = f.info.cuts;
        yields = f.info.yields;
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
    // A bonded bag's bonds join its placed neighbours: placed again for a restart (deterministic).
    const bool bonded = scene.placement && core::hasBonds(*s.model);
    core::Particles placedForBonds;
    std::vector<std::uint8_t> bagParent;
    if (scene.shape && (place || bonded || warn || hasDefaultSeed(scene.timeline))) {
        const GradientMap header = s.options.map->header;
        const GradientMap whole = s.options.map->crop(
            0, bop::VoxelWindow{Eigen::Vector3i::Zero(),
                                Eigen::Vector3i(header.wholeDims().nx, header.wholeDims().ny, header.wholeDims().nz)});
        // The thin parts: said, and held as membranes where the bag is placed (one search for both).
        std::vector<char> membrane;
        if (warn || place || bonded) {
            const std::vector<std::string> thin =
                shape::thinPartsWarnings(whole, scene.shape->bagNames(), place || bonded ? &membrane : nullptr);
            if (warn)
                for (const std::string& w : thin) progress("warning: " + w);
        }
        PieceSeeding seeding = seedEveryPiece(*s.model, whole, scene.construction, s.timeline);
        s.timeline = std::move(seeding.timeline);  // every process alike, from the same map
        if (warn && !place)
            for (const std::string& n : seeding.notes) progress(n);
        if (place || bonded) {  // every process places on the whole map alike and keeps what it owns (core::Run)
            app::PlacementParams params = *scene.placement;
            params.membrane = &membrane;
            app::Placement placed = app::placeParticles(*s.model, whole, params);
            if (root && progress && place) progress(placementReport(*s.model, placed.species));
            if (bonded) {
                placedForBonds = placed.particles;
                bagParent = whole.bagParent;
            }
            if (place) s.particles = std::move(placed.particles);
        }
    }
    core::Construction construction({}, {}, s.model->speciesCount());
    core::Particles fromFile = initialParticles(scene, *s.model, s.timeline, restart, s.firstStep, construction,
                                                s.settle, s.options.cuts, s.options.yields);
    s.settleFile = restart;
    if (!place) s.particles = std::move(fromFile);
    if (bonded) {
        if (!restart.empty()) checkPlacedIds(placedForBonds, s.particles, *s.model, restart, !s.options.cuts.empty());
        auto model = std::make_shared<core::Model>(*s.model);
        model->bonds = std::make_shared<const core::BondNetwork>(
            core::buildBonds(*model, placedForBonds, core::bondCut(*model, scene.params), bagParent,
                             scene.supportBelowMm ? model->units.fromMm(*scene.supportBelowMm) : 0.0));
        if (root && progress) progress(bondReport(*model->bonds, placedForBonds.size()));
        s.model = std::move(model);
    }
    s.options.firstStep = s.firstStep;
    s.options.params = scene.params;
    s.options.params->probe = s.probe;
    if (bonded)  // bonds hold joined bags together: no LJ between them (app/scene/Material.hpp)
        for (int a = 1; a <= s.model->speciesCount(); ++a)
            for (int b = 1; b <= s.model->speciesCount(); ++b)
                if (core::bondedBags(bagParent, a, b)) s.options.params->lj(a, b) = 0;
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
