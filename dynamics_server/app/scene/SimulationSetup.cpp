#include "app/scene/SimulationSetup.hpp"

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

void printFidelity(std::ostream& out, const Fidelity& f) {
    out << "shape fidelity: " << std::setprecision(3) << 100 * f.surfaceInOwnVoxels
        << "% of surface particles in their surface voxels, " << 100 * f.volumeInOwnVoxels
        << "% of volume particles in their volume voxels, median normal angle " << std::setprecision(2)
        << f.medianNormalAngleDeg << " deg\n"
        << std::setprecision(6);
    for (const BagFidelity& b : f.bags)
        out << "  bag '" << b.name << "': " << std::setprecision(3) << 100 * b.surfaceInOwnVoxels << "% of its "
            << b.surface << " surface particles in its surface voxels, " << 100 * b.volumeInOwnVoxels << "% of its "
            << b.volume << " volume particles in its volume voxels, " << std::setprecision(4) << 100 * b.insideBag
            << "% of its particles inside it, median normal angle " << std::setprecision(2) << b.medianNormalAngleDeg
            << " deg\n"
            << std::setprecision(6);
}

namespace {

double median(std::vector<double>& v) {  // 0 for none; the upper one of an even count
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

Fidelity measureFidelity(const core::Model& model, const GradientMap& m, const core::Particles& p) {
    Fidelity f;
    const double h = voxelLength(m.r0Voxels);
    std::size_t surfaceIn = 0, volumeIn = 0;
    std::vector<double> angles;
    std::vector<std::vector<double>> bagAngles;  // per bag
    // Every bag, one alone too (its particles inside it): its surface and volume species 2k - 1, 2k.
    const int bags = model.hasSurfaceSpecies() ? std::min(m.bagCount, (model.speciesCount() + 1) / 2) : 0;
    std::vector<std::size_t> ownSurface(std::size_t(bags) + 1, 0), ownVolume(std::size_t(bags) + 1, 0),
        inside(std::size_t(bags) + 1, 0);
    f.bags.resize(std::size_t(bags));
    bagAngles.resize(std::size_t(bags) + 1);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::int64_t voxel = m.voxelHolding(p.pos[i] / h);
        const bool inGrid = voxel >= 0;
        const std::size_t idx = inGrid ? std::size_t(voxel) : 0;
        const bool own = inGrid && m.occ[idx] == p.species[i];
        if (const int bag = bagOfSpecies(p.species[i]); bag <= bags) {
            BagFidelity& b = f.bags[std::size_t(bag) - 1];
            const bool surface = model.isSurface(p.species[i]);
            (surface ? b.surface : b.volume) += 1;
            (surface ? ownSurface : ownVolume)[std::size_t(bag)] += own;
            inside[std::size_t(bag)] += inGrid && bagOfSpecies(m.occ[idx]) == bag;
        }
        if (model.isSurface(p.species[i])) {
            ++f.surface;
            surfaceIn += own;
            if (inGrid) {
                const double cosA = std::clamp(p.normal[i].dot(m.nearestSurface(idx).normal.cast<double>()), -1.0, 1.0);
                angles.push_back(std::acos(cosA) * 180.0 / M_PI);
                if (const int bag = bagOfSpecies(p.species[i]); bag <= bags)
                    bagAngles[std::size_t(bag)].push_back(angles.back());
            }
        } else {
            ++f.volume;
            volumeIn += own;
        }
    }
    f.surfaceInOwnVoxels = f.surface ? double(surfaceIn) / double(f.surface) : 0;
    f.volumeInOwnVoxels = f.volume ? double(volumeIn) / double(f.volume) : 0;
    for (int bag = 1; bag <= bags; ++bag) {
        BagFidelity& b = f.bags[std::size_t(bag) - 1];
        b.name = model.species[std::size_t(surfaceSpeciesOfBag(bag))].name;
        if (b.name.size() > 8 && b.name.ends_with("-surface")) b.name.resize(b.name.size() - 8);
        b.surfaceInOwnVoxels = b.surface ? double(ownSurface[std::size_t(bag)]) / double(b.surface) : 0;
        b.volumeInOwnVoxels = b.volume ? double(ownVolume[std::size_t(bag)]) / double(b.volume) : 0;
        b.insideBag = b.surface + b.volume ? double(inside[std::size_t(bag)]) / double(b.surface + b.volume) : 0;
    }
    f.medianNormalAngleDeg = median(angles);
    for (int bag = 1; bag <= bags; ++bag)
        f.bags[std::size_t(bag) - 1].medianNormalAngleDeg = median(bagAngles[std::size_t(bag)]);
    return f;
}

}  // namespace bop::app
