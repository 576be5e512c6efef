// bop-cluster-proto: the cluster-pair prototype (ClusterPairProto.hpp) against BoP's own pair
// loops, on one workload in one run. The workload: scripts/bench/step.sh's bulk box (fcc at r0,
// each site moved up to 0.05 r0 per axis, periodic), every particle a surface particle with its
// normal within 30 degrees of z, so that both loops run: the LJ loop at its cutoff (switched,
// 1.6 r0) and the oriented loop at the weight's (3 r0). For each loop: the prototype's pairs
// computed and in range (its useful share), ns per pair computed and per pair in range (one core,
// best of --repeats passes), BoP's loops' CPU ns per pair in range in double and in mixed
// precision over --steps steps, and the prototype's gain over each. With --scene and --restart,
// a built bag besides (the torus of scripts/bench/bag.sh): every particle for the LJ loop, the
// surface particles for the oriented loop. The cluster list reaches the cutoff + 0.05 r0, as the
// loops' pruned lists do. Then, per workload, the layout's LJ loop as built in the form the core
// would run it (ClusterForm.hpp: double differences and sums, the list's own pairs) against the
// core's LJ loop over the same pruned list in double and mixed, its forces checked against the
// latter's (exit 1 if they differ by more than 1e-5 of their size).
#include "ClusterForm.hpp"
#include "ClusterPairProto.hpp"
#include "app/scene/RunStart.hpp"
#include "app/scene/SceneConfig.hpp"
#include "core/Run.hpp"
#include "core/TargetClones.hpp"
#include "core/Threads.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

namespace bop::tools {
namespace {

// Particles to time both loops on, and a run of BoP's that holds them.
struct Workload {
    std::string name;
    std::shared_ptr<core::Model> model;
    core::Particles particles;
    core::SimulationOptions options;
    // The prototype's inputs: every particle (the LJ loop) and the surface ones (the oriented).
    std::vector<Eigen::Vector3d> pos, normal, surfacePos, surfaceNormal;
    void collect() {
        for (std::size_t i = 0; i < particles.size(); ++i) {
            const Eigen::Vector3d n = particles.q[i] * Eigen::Vector3d::UnitZ();
            pos.push_back(particles.pos[i]), normal.push_back(n);
            if (model->isSurface(particles.species[i]))
                surfacePos.push_back(particles.pos[i]), surfaceNormal.push_back(n);
        }
    }
};

// step.sh's bulk box, every particle on a surface species with weights 1 (both loops run).
Workload fccBox(int cells) {
    Workload w;
    const double a = std::sqrt(2.0) * kR0, side = cells * a;
    w.model = std::make_shared<core::Model>();
    w.model->species.assign(2, core::Species{});
    w.model->species[1].kind = core::ParticleKind::Surface;
    w.model->box.hi = Eigen::Vector3d::Constant(side);
    w.model->box.periodic = {true, true, true};
    w.model->integration.dt = 0.002;
    core::Params p(1);
    p.coNormal(1, 1) = p.coPlanar(1, 1) = 1.0;
    w.options.params = p;
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> u(-0.05 * kR0, 0.05 * kR0), unit(0.0, 1.0);
    const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j)
            for (int k = 0; k < cells; ++k)
                for (const auto& o : basis) {
                    const Eigen::Vector3d x =
                        Eigen::Vector3d(i + o[0], j + o[1], k + o[2]) * a + Eigen::Vector3d(u(rng), u(rng), u(rng));
                    const double tilt = std::acos(1.0 - unit(rng) * (1.0 - std::cos(M_PI / 6)));
                    const double turn = 2 * M_PI * unit(rng);
                    const Eigen::Quaterniond q(
                        Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(turn), std::sin(turn), 0)));
                    w.particles.add(x, 1, w.particles.size() + 1, q);
                }
    w.name = "fcc box";
    w.collect();
    return w;
}

// A built bag: a scene and the state to start from (bop-server's final.xyz), as bop-server starts it.
Workload builtScene(const std::string& scene, const std::string& restart, const std::string& cache) {
    app::RunStart s = app::startRun(app::loadScene(scene), cache, restart, true, [] {});
    Workload w;
    w.model = std::make_shared<core::Model>(*s.model);
    w.particles = s.particles;
    w.options = std::move(s.options);
    w.name = std::filesystem::path(scene).stem().string();
    w.collect();
    return w;
}

struct LoopTimes {
    double ljNs = 0, orientedNs = 0;  // CPU ns per pair in range
};

// BoP's loops over `steps` steps of the workload, the set-up's forces left out.
LoopTimes bopLoops(const Workload& w, bool mixed, int steps) {
    auto m = std::make_shared<core::Model>(*w.model);
    m->integration.mixedPrecision = mixed;
    core::Run run(m, w.particles, w.options);  // as bop-server runs it (one process)
    run.setEnergyEvery(steps);                 // as a batch run between its reports: forces alone
    run.resetTimes();
    run.run(steps);
    const core::PhaseTimes& t = run.simulation().times().forces;
    return {1e9 * t.ljLoopSeconds / std::max(t.ljPairs, 1.0),
            1e9 * t.orientedLoopSeconds / std::max(t.orientedPairs, 1.0)};
}

}  // namespace
}  // namespace bop::tools

int main(int argc, char** argv) {
    using namespace bop;
    CLI::App app{
        "bop-cluster-proto: a cluster-pair layout's prototype kernels against BoP's pair loops on the bulk "
        "box, both loops (LJ at 1.6 r0, oriented at 3 r0), one core; then the layout's LJ loop as built in the "
        "core's form (double differences and sums) against the core's LJ loop on the same list, its forces "
        "checked (exit 1 past 1e-5 of their size)"};
    std::vector<int> cells{14};
    int repeats = 5, steps = 200;
    std::string csvPath, scene, restart, cache;
    app.add_option("--cells", cells, "fcc cells per box edge, one or more (14: 10,976 particles; 29: 97,556)")
        ->check(CLI::Range(4, 200));
    app.add_option("--repeats", repeats, "timed passes of each prototype kernel, the best kept")
        ->check(CLI::Range(1, 100));
    app.add_option("--steps", steps, "steps of BoP's run in each precision")->check(CLI::Range(10, 100000));
    app.add_option("--csv", csvPath, "also write the table as CSV to this file");
    app.add_option("--scene", scene, "also a built bag: its scene file (with --restart)")->check(CLI::ExistingFile);
    app.add_option("--restart", restart, "the bag's built state (bop-server's final.xyz)")->check(CLI::ExistingFile);
    app.add_option("--cache", cache, "the bag's gradient-map cache (built there if missing)");
    CLI11_PARSE(app, argc, argv);
    if (scene.empty() != restart.empty() || (!scene.empty() && cache.empty())) {
        std::fprintf(stderr, "bop-cluster-proto: --scene, --restart and --cache go together\n");
        return 2;
    }
    core::setThreadCount(1);
    const core::LjForm lj;
    const core::OrientedWeight weight;
    std::FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
    if (!csvPath.empty() && !csv) {
        std::fprintf(stderr, "bop-cluster-proto: cannot write '%s'\n", csvPath.c_str());
        return 1;
    }
    if (csv)
        std::fprintf(csv,
                     "workload,particles,loop,cutoff_r0,computed,in_range,useful_share,ns_per_computed,"
                     "ns_per_in_range,bop_double_ns,bop_mixed_ns,gain_over_double,gain_over_mixed,clone\n");
    std::printf("pair loops and prototype: the %s clone; one core\n", core::hotLoopClone());
    std::printf("%-9s %9s %-9s %9s %10s %7s %8s %8s %9s %9s %7s %7s\n", "workload", "particles", "loop", "computed",
                "in range", "share", "ns/comp", "ns/in", "BoP dbl", "BoP mix", "gain/d", "gain/m");
    std::vector<tools::Workload> loads;
    for (const int c : cells) loads.push_back(tools::fccBox(c));
    if (!scene.empty()) loads.push_back(tools::builtScene(scene, restart, cache));
    for (const tools::Workload& w : loads) {
        const tools::LoopTimes dbl = tools::bopLoops(w, false, steps), mix = tools::bopLoops(w, true, steps);
        const core::Box& box = w.model->box;
        for (const bool oriented : {false, true}) {
            const double cutoff = oriented ? weight.cutoff() : lj.cutoff();
            const tools::ClusterSet set =
                tools::buildClusters(oriented ? w.surfacePos : w.pos, oriented ? w.surfaceNormal : w.normal, box.lo,
                                     box.hi, box.periodic[0], cutoff + 0.05 * kR0);
            const tools::ClusterPass pass =
                oriented ? tools::orientedClusterPass(set, weight, repeats) : tools::ljClusterPass(set, lj, repeats);
            const double share = double(pass.inRange) / double(pass.computed);
            const double perComputed = 1e9 * pass.seconds / double(pass.computed);
            const double perInRange = 1e9 * pass.seconds / double(pass.inRange);
            const double bopD = oriented ? dbl.orientedNs : dbl.ljNs, bopM = oriented ? mix.orientedNs : mix.ljNs;
            const char* loop = oriented ? "oriented" : "LJ";
            std::printf("%-9s %9zu %-9s %9zu %10zu %7.3f %8.3f %8.2f %9.2f %9.2f %6.2fx %6.2fx\n", w.name.c_str(),
                        w.pos.size(), loop, pass.computed, pass.inRange, share, perComputed, perInRange, bopD, bopM,
                        bopD / perInRange, bopM / perInRange);
            if (csv)
                std::fprintf(csv, "%s,%zu,%s,%.3f,%zu,%zu,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%s\n", w.name.c_str(),
                             w.pos.size(), loop, cutoff / kR0, pass.computed, pass.inRange, share, perComputed,
                             perInRange, bopD, bopM, bopD / perInRange, bopM / perInRange, core::hotLoopClone());
        }
    }
    // The layout as built, its LJ loop against the core's on the same list ("LJ built" rows).
    int failed = 0;
    for (const tools::Workload& w : loads) {
        const tools::ClusterFormResult r =
            tools::measureClusterForm(*w.model, w.options.params.value_or(core::Params(w.model->speciesCount())),
                                      w.particles, w.model->box, repeats);
        const std::size_t computed = 16 * r.clusterPairs;
        const double share = double(r.inRange) / double(std::max<std::size_t>(computed, 1));
        const double perComputed = r.clusterNs * double(r.inRange) / double(std::max<std::size_t>(computed, 1));
        std::printf("%-9s %9zu %-9s %9zu %10zu %7.3f %8.3f %8.2f %9.2f %9.2f %6.2fx %6.2fx\n", w.name.c_str(),
                    w.pos.size(), "LJ built", computed, r.inRange, share, perComputed, r.clusterNs, r.rowsDoubleNs,
                    r.rowsMixedNs, r.rowsDoubleNs / r.clusterNs, r.rowsMixedNs / r.clusterNs);
        std::printf(
            "  built against the rows in double: forces %.2e of their size, virial %.2e, energy %.2e, "
            "pairs in range %s\n",
            r.forceDifference, r.virialDifference, r.energyDifference, r.sameCount ? "the same" : "DIFFER");
        if (!(r.forceDifference <= 1e-5 && r.virialDifference <= 1e-5 && r.energyDifference <= 1e-9 && r.sameCount)) {
            std::fprintf(stderr, "bop-cluster-proto: the built cluster loop disagrees with the rows on %s\n",
                         w.name.c_str());
            failed = 1;
        }
        if (csv)
            std::fprintf(csv, "%s,%zu,LJ built,%.3f,%zu,%zu,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%.3f,%s\n", w.name.c_str(),
                         w.pos.size(), lj.cutoff() / kR0, computed, r.inRange, share, perComputed, r.clusterNs,
                         r.rowsDoubleNs, r.rowsMixedNs, r.rowsDoubleNs / r.clusterNs, r.rowsMixedNs / r.clusterNs,
                         core::hotLoopClone());
    }
    if (csv) std::fclose(csv);
    return failed;
}
