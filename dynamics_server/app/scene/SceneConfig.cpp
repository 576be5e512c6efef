#include "app/scene/SceneConfig.hpp"

#include "bop/common/BagColours.hpp"
#include "bop/common/ConfigTable.hpp"
#include "codec/Ranges.hpp"
#include "core/Construction.hpp"

#include <algorithm>
#include <cmath>

namespace bop::app {
namespace {

// The most steps a placed bag runs to settle when [run] steps is not given.
constexpr long long kPlacedStepsCap = 20000;

using core::kR0;

double positive(const ConfigTable& t, const std::string& key, double v) {
    if (!(v > 0)) t.fail(key, "must be greater than 0, got " + std::to_string(v));
    return v;
}

void readMatrix(const ConfigTable& t, const std::string& key, core::WeightMatrix& m) {
    if (!t.has(key)) return;
    const toml::array* rows = t.raw().get(key)->as_array();
    const int n = m.n - 1;
    if (!rows || int(rows->size()) != n)
        t.fail(key, "expected " + std::to_string(n) + " rows of " + std::to_string(n) + " numbers (one per species)");
    for (int a = 0; a < n; ++a) {
        const toml::array* row = (*rows)[std::size_t(a)].as_array();
        if (!row || int(row->size()) != n)
            t.fail(key, "row " + std::to_string(a + 1) + ": expected " + std::to_string(n) + " numbers");
        for (int b = 0; b < n; ++b) {
            const auto v = (*row)[std::size_t(b)].value<double>();
            if (!v || *v < 0) t.fail(key, "row " + std::to_string(a + 1) + ": expected numbers >= 0");
            m(a + 1, b + 1) = *v;
        }
    }
}

// [plasticity]: a dent held (hold_time, simulation time units) or pressed deep (yield_depth_r0)
// becomes the rest shape (core/Plasticity.hpp). Bags the map alone holds: bonds keep their own.
void readPlasticity(const ConfigTable& root, const Scene& s, core::Model& m) {
    const auto t = root.optionalTable("plasticity");
    if (!t) return;
    core::PlasticityParams& p = m.plasticity;
    p.on = t->boolean("enabled", true);
    if (!s.shape) t->fail("enabled", "plasticity moves a bag's map: a bulk [box] has none");
    if (p.on && !s.materials.empty())
        t->fail("enabled",
                "the scene's [[material]] bonds its bags, and bonds keep their rest shape: plasticity is "
                "for bags the map alone holds");
    p.holdTime = t->number("hold_time", 0.0);
    p.yieldDepthR0 = t->number("yield_depth_r0", 0.0);
    p.bandR0 = positive(*t, "band_r0", t->number("band_r0", p.bandR0));
    if (!(p.holdTime >= 0)) t->fail("hold_time", "expected a time of 0 (only by depth) or more");
    if (!(p.yieldDepthR0 >= 0)) t->fail("yield_depth_r0", "expected a depth of 0 (only by time) or more");
    if (p.on && p.holdTime == 0 && p.yieldDepthR0 == 0)
        t->fail("hold_time", "give hold_time, yield_depth_r0 or both: nothing would ever yield");
    const double every = t->number("every_steps", double(p.everySteps));
    if (!(every >= 1 && every <= 1e6 && every == std::floor(every)))
        t->fail("every_steps", "expected a whole number of steps from 1");
    p.everySteps = (long long)every;
    t->finish();
}

// kindsFromMap: species kinds follow the map numbering (bag k: 2k-1 surface, 2k volume).
void readSpecies(const ConfigTable& root, core::Model& m, core::Params& params, bool kindsFromMap) {
    if (!root.has("species")) return;
    const std::vector<ConfigTable> list = root.tableArray("species");
    if (int(list.size()) != m.speciesCount())
        root.fail("species", "expected " + std::to_string(m.speciesCount()) +
                                 " [[species]] tables (one per species number" + (kindsFromMap ? ", 2 per bag" : "") +
                                 "), got " + std::to_string(list.size()));
    for (std::size_t i = 0; i < list.size(); ++i) {
        const ConfigTable& t = list[i];
        core::Species& s = m.species[i + 1];
        s.name = t.string("name", s.name);
        if (s.name.find_first_of(" \t\"") != std::string::npos) t.fail("name", "must not contain spaces or quotes");
        const std::string kind =
            t.choice("kind", {"surface", "volume"}, s.kind == core::ParticleKind::Surface ? "surface" : "volume");
        const auto wanted = kind == "surface" ? core::ParticleKind::Surface : core::ParticleKind::Volume;
        if (kindsFromMap && wanted != s.kind)
            t.fail("kind", "species " + std::to_string(i + 1) + " is a " +
                               (s.kind == core::ParticleKind::Surface ? "surface" : "volume") +
                               " species of the map (bag k has surface species 2k-1 and volume species 2k)");
        s.kind = wanted;
        if (t.has("colour")) {
            const Eigen::Vector3d c = t.vec3("colour");
            if (c.minCoeff() < 0 || c.maxCoeff() > 1) t.fail("colour", "expected 3 numbers in [0, 1]");
            s.colour = {float(c.x()), float(c.y()), float(c.z())};
        }
        s.alphaForceOp = t.number("alpha_f_op", s.alphaForceOp);
        s.alphaForceGm = t.number("alpha_f_gm", s.alphaForceGm);
        s.alphaTorqueOp = t.number("alpha_tau_op", s.alphaTorqueOp);
        s.alphaTorqueGm = t.number("alpha_tau_gm", s.alphaTorqueGm);
        core::Drag& drag = params.drag[i + 1];
        drag.v = t.number("drag_v", drag.v);
        drag.w = t.number("drag_w", drag.w);
        t.finish();
    }
}

void readDynamics(const ConfigTable& root, core::Model& m, std::uint64_t& seed) {
    const auto t = root.optionalTable("dynamics");
    if (!t) return;
    m.integration.dt = positive(*t, "time_step", t->number("time_step", m.integration.dt));
    m.integration.inertia = positive(*t, "inertia", t->number("inertia", m.integration.inertia));
    m.integration.skinR0 = t->number("neighbour_skin_r0", m.integration.skinR0);
    if (!(m.integration.skinR0 >= 0 && m.integration.skinR0 <= 2))
        t->fail("neighbour_skin_r0", "expected a skin from 0 to 2 r0");
    m.integration.pruneR0 = t->number("neighbour_prune_r0", m.integration.pruneR0);
    if (!(m.integration.pruneR0 >= 0 && m.integration.pruneR0 <= 2))
        t->fail("neighbour_prune_r0", "expected 0 (no pruning) or an inner skin up to 2 r0");
    m.integration.maxStepR0 = t->number("max_step_r0", m.integration.maxStepR0);
    if (!(m.integration.maxStepR0 >= 0 && m.integration.maxStepR0 <= 10))
        t->fail("max_step_r0", "expected 0 (no limit) or the most a particle moves in a step, up to 10 r0");
    m.integration.maxTurn = t->number("max_turn_rad", m.integration.maxTurn);
    if (!(m.integration.maxTurn >= 0 && m.integration.maxTurn <= 3.15))
        t->fail("max_turn_rad", "expected 0 (no limit) or the most a particle turns in a step, up to pi radians");
    const std::string mode =
        t->choice("lj_cutoff", {"switched", "paper", "energy_shifted", "shifted_force"}, "switched");
    m.ljParams.mode = mode == "switched"         ? core::LjCutoff::Switched
                      : mode == "paper"          ? core::LjCutoff::Truncated
                      : mode == "energy_shifted" ? core::LjCutoff::EnergyShifted
                                                 : core::LjCutoff::ShiftedForce;
    if (mode == "switched") {
        const std::vector<double> sw =
            t->has("lj_switch_r0") ? t->numbers("lj_switch_r0") : std::vector<double>{1.2, 1.6};
        if (sw.size() != 2 || !(0 < sw[0] && sw[0] < sw[1]))
            t->fail("lj_switch_r0", "expected [start, cutoff] with 0 < start < cutoff");
        m.ljParams.rOnR0 = sw[0];
        m.ljParams.rCutR0 = sw[1];
    } else {
        m.ljParams.rCutR0 = positive(*t, "lj_cutoff_r0", t->number("lj_cutoff_r0", 3.0));
    }
    m.oriented.sigmaR0 = positive(*t, "oriented_sigma_r0", t->number("oriented_sigma_r0", m.oriented.sigmaR0));
    if (t->has("oriented_taper_r0")) {
        const std::vector<double> tp = t->numbers("oriented_taper_r0");
        if (tp.size() != 2 || !(0 < tp[0] && tp[0] < tp[1]))
            t->fail("oriented_taper_r0", "expected [start, cutoff] with 0 < start < cutoff");
        m.oriented.taperOnR0 = tp[0];
        m.oriented.cutoffR0 = tp[1];
    }
    m.curvatureWeighting = t->boolean("curvature_weighting", m.curvatureWeighting);
    m.integration.mixedPrecision = t->choice("precision", {"double", "mixed"}, "double") == "mixed";
    seed = std::uint64_t(t->integer("seed", 1));
    t->finish();
}

void readConstruction(const ConfigTable& root, Scene& s) {
    s.construction.seed = s.seed;
    const auto t = root.optionalTable("construction");
    // No timeline: the bag is placed on its map and settles (docs/scene-format.md).
    const bool events = t && t->has("event");
    const std::string fallback = events || !s.shape ? "birth" : "place";
    const std::string method = t ? t->choice("method", {"place", "birth"}, fallback) : fallback;
    if (method == "place" && s.shape) {
        if (events)
            t->fail("method", "\"place\" sets every particle at the start; drop the [[construction.event]] list");
        app::PlacementParams p;
        p.seed = s.seed;
        if (t) p.gapR0 = t->number("gap_r0", p.gapR0);
        if (!(p.gapR0 >= 0)) t->fail("gap_r0", "expected a distance of 0 or more, in r0");
        if (t && t->choice("sheet_area", {"faces", "mid-shell"}, "faces") == "mid-shell")
            p.sheetArea = app::SheetArea::MidShell;
        s.placement = p;
        s.run.untilSettled = t ? t->boolean("until_settled", true) : true;
        if (t) s.run.settleKinetic = t->number("settle_kinetic", s.run.settleKinetic);
        if (!(s.run.settleKinetic > 0)) t->fail("settle_kinetic", "expected a positive energy per particle");
        if (t) s.run.settleEverySteps = t->integer("settle_every_steps", s.run.settleEverySteps);
        if (s.run.settleEverySteps < 1) t->fail("settle_every_steps", "expected at least 1 step");
        if (t) s.run.settleCalmSteps = t->integer("settle_calm_steps", s.run.settleCalmSteps);
        if (s.run.settleCalmSteps < 0) t->fail("settle_calm_steps", "expected 0 steps or more");
        s.run.settleTimeStep = std::min(0.03, 1.5 * s.model->integration.dt);
        if (t) s.run.settleTimeStep = t->number("settle_time_step", s.run.settleTimeStep);
        if (!(s.run.settleTimeStep > 0)) t->fail("settle_time_step", "expected a positive time step");
        if (t && t->choice("settle_method", {"fire", "dynamics"}, "fire") == "dynamics") s.run.settleFire.reset();
        if (t && s.run.settleFire) {
            double& f = s.run.settleFire->dtMaxFactor;
            f = t->number("fire_dt_max", f * s.run.settleTimeStep) / s.run.settleTimeStep;
            if (!(f >= 1)) t->fail("fire_dt_max", "expected a time step of at least settle_time_step");
            long long& m = s.run.settleFire->maxSteps;
            m = t->integer("fire_max_steps", m);
            if (m < 1) t->fail("fire_max_steps", "expected at least 1 step");
        }
    } else if (method == "place") {
        t->fail("method", "\"place\" sets particles on a [shape]'s map; the scene has none");
    }
    if (!t) return;
    auto& c = s.construction;
    c.everySteps = int(t->integer("every_steps", c.everySteps));
    c.deathR0 = t->number("death_r0", c.deathR0);
    c.sameR0 = t->number("same_r0", c.sameR0);
    c.anyR0 = t->number("any_r0", c.anyR0);
    c.frontR0 = t->number("front_r0", c.frontR0);
    c.capFraction = t->number("cap_fraction", c.capFraction);
    if (events)
        for (const ConfigTable& e : t->tableArray("event")) {
            core::ConstructionEvent ev;
            ev.step = e.integer("step");
            if (ev.step < 0) e.fail("step", "must be 0 or more");
            const std::string a = e.choice("action", {"seed", "birth_on", "birth_off"}, "");
            ev.action = a == "seed"       ? core::ConstructionEvent::Action::Seed
                        : a == "birth_on" ? core::ConstructionEvent::Action::BirthOn
                                          : core::ConstructionEvent::Action::BirthOff;
            ev.species = int(e.integer("species"));
            if (ev.species < 1 || ev.species > s.model->speciesCount())
                e.fail("species", "expected a species number from 1 to " + std::to_string(s.model->speciesCount()));
            if (e.has("position_voxels")) ev.positionVoxels = e.vec3("position_voxels");
            e.finish();
            s.timeline.push_back(ev);
        }
    t->finish();
}

// [keyframes]: the frames come from the shape's image sequence.
void readKeyframes(const ConfigTable& root, const Scene& s, core::KeyframeSchedule& k) {
    const auto t = root.optionalTable("keyframes");
    if (!t) return;
    if (!s.shape) root.fail("keyframes", "keyframes cycle the frames of a [shape]; the scene has none");
    for (const auto& bag : s.shape->bags) k.frames = std::max(k.frames, bag.source->frameCount());
    if (k.frames < 2)
        root.fail("keyframes",
                  "the shape has one frame; keyframes need an image sequence (a 4D NIfTI or files = [...])");
    if (t->has("period") == t->has("frame_duration"))
        t->fail("frame_duration", "give either period or frame_duration (simulation time units), not both or neither");
    const auto finite = [&](const std::string& key, double v) {
        if (!std::isfinite(v)) t->fail(key, "expected a finite number");
        return v;
    };
    const double dt = s.model->integration.dt;
    k.frameDuration = t->has("period") ? finite("period", t->number("period")) / k.frames
                                       : finite("frame_duration", t->number("frame_duration"));
    if (!(k.frameDuration >= dt))
        t->fail(t->has("period") ? "period" : "frame_duration", "each frame must last at least one time step (" +
                                                                    std::to_string(dt) + "), got " +
                                                                    std::to_string(k.frameDuration) + " per frame");
    k.startTime = finite("start_time", t->number("start_time", 0.0));
    if (k.startTime < 0) t->fail("start_time", "expected 0 or more (simulation time units)");
    const long long first = t->integer("first_frame", 0);
    if (first < 0 || first >= k.frames)
        t->fail("first_frame", "expected a frame in [0, " + std::to_string(k.frames - 1) + "]");
    k.firstFrame = int(first);
    k.blend = t->boolean("blend", true);
    t->finish();
}

// [units]: mass scaling and pacing, for scenes with materials.
void readUnits(const ConfigTable& root, Scene& s, core::Model& m) {
    double massScaling = 1;
    if (const auto t = root.optionalTable("units")) {
        if (s.materials.empty())
            t->fail("mass_scaling", "units are physical only with [[material]] tables; the scene has none");
        massScaling = t->number("mass_scaling", 1.0);
        if (!(massScaling >= 1 && massScaling <= 1e12)) t->fail("mass_scaling", "expected a factor of 1 or more");
        s.realTime = t->boolean("real_time", true);
        t->finish();
    }
    if (s.materials.empty()) return;
    s.calibration = calibrate(s.materials, m.units.lengthMm, massScaling);
    m.units = s.calibration->units;
    applyCalibration(*s.calibration, s.materials, m, s.params);
}

}  // namespace

void defaultSpecies(core::Model& m, core::Params& params, int bags) {
    const int n = 2 * bags;
    m.species.assign(std::size_t(n) + 1, core::Species{});
    for (int s = 1; s <= n; ++s) {
        core::Species& sp = m.species[std::size_t(s)];
        sp.kind = s % 2 ? core::ParticleKind::Surface : core::ParticleKind::Volume;
        sp.name = "bag" + std::to_string((s + 1) / 2) + (s % 2 ? "-surface" : "-volume");
        sp.colour = defaultSpeciesColour(s);
    }
    params = core::Params(n);
    for (int s = 1; s <= n; s += 2) params.coNormal(s, s) = params.coPlanar(s, s) = 0.3;  // docs/physics.md §7.4
}

Scene loadScene(const std::string& path) {
    const toml::table doc = ConfigTable::parseFile(path);
    const ConfigTable root(doc, path, "");
    Scene s;
    s.file = path;
    auto model = std::make_shared<core::Model>();  // the scene's own until it is parsed, then constant
    s.model = model;
    core::Model& m = *model;
    if (root.has("box")) {
        if (root.has("shape"))
            root.fail("box", "give either [box] (bulk material) or [grid] and [shape] (bags), not both");
        const ConfigTable b = root.table("box");
        BulkBox bulk;
        bulk.sizeR0 = b.vec3("size_r0", bulk.sizeR0);
        bulk.spacingR0 = positive(b, "spacing_r0", b.number("spacing_r0", bulk.spacingR0));
        bulk.jitterR0 = b.number("jitter_r0", 0.0);
        const bool periodic = b.boolean("periodic", true);
        b.finish();
        if (bulk.sizeR0.minCoeff() <= 0) b.fail("size_r0", "expected 3 positive numbers");
        m.box.lo.setZero();
        m.box.hi = bulk.sizeR0 * kR0;
        m.box.periodic = {periodic, periodic, periodic};
        m.species.assign(2, core::Species{});
        m.species[1].name = "bulk";
        m.species[1].colour = defaultSpeciesColour(2);
        s.params = core::Params(1);
        s.bulk = bulk;
    } else {
        s.shape = shape::readShapeSpec(root);
        m.interpolation = s.shape->interpolation;
        m.mapGeometry = s.shape->geometry;
        defaultSpecies(m, s.params, int(s.shape->bags.size()));
        for (std::size_t b = 0; b < s.shape->bags.size(); ++b) {
            m.species[2 * b + 1].name = s.shape->bags[b].name + "-surface";
            m.species[2 * b + 2].name = s.shape->bags[b].name + "-volume";
            if (const auto& c = s.shape->bags[b].colour) {  // a label table's: the sheet, the volume darker
                m.species[2 * b + 1].colour = *c;
                m.species[2 * b + 2].colour = {0.6f * (*c)[0], 0.6f * (*c)[1], 0.6f * (*c)[2]};
            }
        }
    }
    readSpecies(root, m, s.params, s.shape.has_value());
    if (s.shape) {
        std::vector<std::string> names;
        for (const auto& bag : s.shape->bags) names.push_back(bag.name);
        s.materials = readMaterials(root, names);
        m.units.lengthMm = lengthMmOf(s.shape->grid.voxelMm, s.shape->grid.r0Voxels);
    } else if (root.has("material")) {
        root.fail("material", "a material is a bag's; a bulk [box] has none");
    }
    if (!s.materials.empty() && root.has("interactions"))
        root.fail("interactions", "the [[material]] tables set the weights; give either, not both");
    if (const auto t = root.optionalTable("interactions")) {
        readMatrix(*t, "lj", s.params.lj);
        readMatrix(*t, "co_normal", s.params.coNormal);
        readMatrix(*t, "co_planar", s.params.coPlanar);
        t->finish();
    }
    readDynamics(root, m, s.seed);
    readUnits(root, s, m);
    if (s.bulk && m.hasSurfaceSpecies()) root.fail("species", "a bulk [box] holds volume particles only");
    readConstruction(root, s);
    if (!s.materials.empty() && !s.placement)
        root.fail("construction",
                  "a bag with a [[material]] is placed (method = \"place\"): its bonds join the "
                  "placed neighbours");
    if (s.placement) s.placement->flatSheet = !s.materials.empty();
    if (const auto t = root.optionalTable("support")) {
        if (s.materials.empty()) t->fail("below_mm", "a support anchors a bonded bag: the scene has no [[material]]");
        s.supportBelowMm = positive(*t, "below_mm", t->number("below_mm"));
        t->finish();
    }
    if (s.placement) s.run.steps = kPlacedStepsCap;
    readPlasticity(root, s, m);
    if (const auto t = root.optionalTable("probe")) {
        s.probe.active = t->boolean("active", false);
        if (t->has("position_voxels")) s.probePositionVoxels = t->vec3("position_voxels");
        s.probe.position = t->vec3("position", Eigen::Vector3d::Zero());
        // The ranges a client's probe must keep (docs/protocol.md): a viewer's sliders start here.
        const auto within = [&](const char* key, double lo, double hi) {
            const double v = t->number(key, 1.0);
            if (!(v >= lo && v <= hi))
                t->fail(key, "expected a value in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                                 std::to_string(v));
            return v;
        };
        s.probe.params.k0 = within("k0", protocol::ranges::kMinProbeK0, protocol::ranges::kMaxProbeK0);
        s.probe.params.k1 = within("k1", protocol::ranges::kMinProbeK1, protocol::ranges::kMaxProbeK1);
        if (t->has("radius_mm")) {  // the tool as a sphere (docs/physics.md §2.5)
            if (!s.shape) t->fail("radius_mm", "a sphere's radius is in mm of a [shape]'s grid; the scene has none");
            core::ProbeSphere sphere;
            sphere.radius = m.units.fromMm(positive(*t, "radius_mm", t->number("radius_mm")));
            // In multiples of the stiffest bond: a bonded bag's nearest-neighbour spring, else an LJ
            // pair's at its minimum, phi''(r0) = 1/sqrt(3) at weight 1.
            double bond = 1 / kR0;
            if (s.calibration) bond = *std::max_element(s.calibration->bond.begin(), s.calibration->bond.end());
            sphere.stiffness = positive(*t, "contact_stiffness", t->number("contact_stiffness", 10.0)) * bond;
            m.probeSphere = sphere;
        } else if (t->has("contact_stiffness")) {
            t->fail("contact_stiffness", "the contact of a sphere: give radius_mm too");
        }
        t->finish();
    }
    readKeyframes(root, s, m.keyframes);
    if (const auto t = root.optionalTable("pressure")) {
        PressureSettings p;
        p.averageSteps = t->integer("average_steps", p.averageSteps);
        if (p.averageSteps < 1) t->fail("average_steps", "expected at least 1 step");
        p.peakMmHg = positive(*t, "peak_mmhg", t->number("peak_mmhg", p.peakMmHg));
        p.paperEq15 = t->choice("formula", {"standard", "paper_eq15"}, "standard") == "paper_eq15";
        p.skipCycles = int(t->integer("skip_cycles", p.skipCycles));
        if (p.skipCycles < 0) t->fail("skip_cycles", "expected 0 or more cycles");
        p.volumeEverySteps = t->integer("volume_every_steps", p.volumeEverySteps);
        if (p.volumeEverySteps < 1) t->fail("volume_every_steps", "expected at least 1 step");
        t->finish();
        if (!s.shape) t->fail("formula", "the blood pressure is measured in a bag: the scene has no [shape]");
        s.pressure = p;
    }
    if (const auto t = root.optionalTable("run")) {
        s.run.steps = t->integer("steps", s.run.steps);
        s.run.snapshotEverySteps = t->integer("snapshot_every_steps", 0);
        s.run.reportEverySteps = t->integer("report_every_steps", 0);
        t->finish();
    }
    root.finish();
    return s;
}

core::Particles bulkLattice(const Scene& scene) {
    core::Particles p;
    const BulkBox& b = *scene.bulk;
    const double a = b.spacingR0 * kR0 * std::sqrt(2.0);  // fcc cube edge for nearest distance d: a = d sqrt 2
    const Eigen::Vector3d L = scene.model->box.size();
    // Whole fcc cells per edge; an edge of exactly n cells must not lose one to rounding.
    const Eigen::Vector3i n = ((L / a).array() * (1 + 1e-9)).floor().cast<int>().max(1).matrix();
    const Eigen::Vector3d cell = L.cwiseQuotient(n.cast<double>());
    static const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    std::uint64_t id = 1;
    for (int k = 0; k < n.z(); ++k)
        for (int j = 0; j < n.y(); ++j)
            for (int i = 0; i < n.x(); ++i)
                for (const auto& bs : basis) {
                    Eigen::Vector3d x =
                        (Eigen::Vector3d(i + bs[0] + 0.25, j + bs[1] + 0.25, k + bs[2] + 0.25)).cwiseProduct(cell);
                    if (b.jitterR0 > 0)
                        for (int c = 0; c < 3; ++c)
                            x[c] += b.jitterR0 * kR0 *
                                    (double(core::mixHash(scene.seed, id, std::uint64_t(c)) >> 11) * 0x1.0p-53 - 0.5);
                    p.add(x, b.speciesNumber, id++);
                }
    return p;
}

}  // namespace bop::app
