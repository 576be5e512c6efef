#include "app/runs/BatchReport.hpp"

#include <algorithm>
#include <cstdio>
#include <iomanip>

namespace bop::app {

void BatchReport::progress(long long done, long long total, std::chrono::steady_clock::time_point start) {
    const core::Totals t = run_.totals();
    const core::RunCounters c = run_.counters();
    const core::ShapeCounts shape = run_.shapeCounts();
    const double surface = shape.surface;
    if (run_.rank() != 0) return;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    os_ << std::fixed << std::setprecision(0) << "step " << run_.stepNumber() << " (" << std::setprecision(1)
        << 100.0 * double(done) / double(total) << "%)  particles " << std::setprecision(0) << surface << " surface + "
        << t.particles - surface << " volume  E_kin " << std::setprecision(4) << t.kinetic << "  E_pair "
        << t.pairEnergy << "  " << std::setprecision(1) << double(done) / std::max(seconds, 1e-9) << " steps/s"
        << std::endl;
    if (c.births > 0 || c.deaths > 0)
        os_ << "  construction so far: " << std::setprecision(0) << c.births << " births, " << c.deaths << " deaths, "
            << std::setprecision(1) << (c.births + c.deaths) / std::max(seconds, 1e-9) << " per second\n";
    if (run_.simulation().mapInForce().map())
        os_ << "  in their own voxels: " << std::setprecision(1)
            << 100 * shape.surfaceInOwn / std::max(1.0, shape.surface) << "% of surface, "
            << 100 * shape.volumeInOwn / std::max(1.0, shape.volume) << "% of volume particles\n";
}

void BatchReport::phases(long long steps) {
    const core::Simulation& sim = run_.simulation();
    const core::StepTimes& t = sim.times();
    const double total = std::max(t.total(), 1e-12);
    const double perStep = steps > 0 ? 1e3 / double(steps) : 0.0;
    os_ << "\nphase          ms/step   share" << (run_.size() > 1 ? "   (rank 0)" : "") << "\n" << std::fixed;
    auto row = [&](const char* name, double s) {
        os_ << std::left << std::setw(14) << name << std::right << std::setw(8) << std::setprecision(3) << s * perStep
            << std::setw(7) << std::setprecision(1) << 100.0 * s / total << "%\n";
    };
    row("pairs", t.forces.pairs);
    row("neighbours", t.forces.neighbours);
    row("gradient map", t.forces.gradientMap);
    row("probe", t.forces.probe);
    row("integrate", t.integrate);
    row("construction", t.construction);
    const core::NeighbourList& list = sim.forceField().pairs().neighbours();
    const auto perPair = [](double seconds, double pairs) { return pairs > 0 ? seconds / pairs * 1e9 : 0.0; };
    os_ << "pair loops (CPU time over threads): " << std::setprecision(1)
        << perPair(t.forces.ljLoopSeconds, t.forces.ljPairs) << " ns per LJ pair in range, "
        << perPair(t.forces.orientedLoopSeconds, t.forces.orientedPairs) << " ns per oriented pair in range\n";
    const core::ForceStats& f = sim.stats().forces;
    os_ << "neighbour list: built " << list.builds() << " times (set-up included), " << list.pairCount()
        << " LJ pairs within its cutoff + skin (" << f.pairsInRange << " within the cutoff), " << list.widePairCount()
        << " oriented pairs within theirs (" << f.orientedPairsInRange << "), " << list.ghostCount()
        << " periodic images\n";
    const core::PairForces& pairs = sim.forceField().pairs();
    if (pairs.pruneSkin() > 0)
        os_ << "pair loops read the list pruned to each cutoff + " << std::setprecision(3)
            << pairs.pruneSkin() / core::kR0 << " r0: pruned " << pairs.pruned().prunes() << " times, "
            << pairs.pruned().pairCount() << " LJ and " << pairs.pruned().widePairCount()
            << " oriented pairs at the last\n";
}

void BatchReport::summary(long long steps, double seconds) {
    const core::Totals t = run_.totals();
    const double surface = run_.shapeCounts().surface, volume = t.particles - surface;
    const core::RunCounters c = run_.counters();
    if (run_.rank() != 0) return;
    phases(steps);
    const double rate = double(steps) / std::max(seconds, 1e-12);
    os_ << "\n            Surface  Volume   Total   steps/s   particle-steps/s\n"
        << "this run  " << std::setprecision(0) << std::setw(9) << surface << std::setw(8) << volume << std::setw(8)
        << t.particles << std::setw(10) << std::setprecision(1) << rate << std::setw(19) << std::setprecision(0)
        << rate * t.particles << "\n";
    if (run_.size() > 1)
        os_ << run_.size() << " ranks: halo " << std::setprecision(0) << c.haloBytesPerStep
            << " bytes per step, particles per rank max/mean " << std::setprecision(3) << c.imbalance << ", "
            << std::setprecision(0) << c.rebuilds << " rebuilds, " << c.rebalances << " balancings, " << c.migrations
            << " migrations; exchanges took " << std::setprecision(1)
            << 100.0 * c.exchangeSecondsMax / std::max(seconds, 1e-12) << "% of the run on the busiest rank\n";
    const UnitSystem& u = run_.simulation().model().units;
    char energyUnit[64];
    std::snprintf(energyUnit, sizeof energyUnit, " (energy unit %.4g J)", u.energyJ());
    os_ << "births " << std::setprecision(0) << c.births << ", deaths " << c.deaths << "; E_kin "
        << std::setprecision(5) << t.kinetic << ", E_pair " << t.pairEnergy << ", virial " << t.virial
        << (u.physical ? energyUnit : " (simulation units)") << "\n";
    if (u.physical) {  // time in seconds: how far the run got, and against the wall clock
        const double simulated = u.toS(double(steps) * run_.simulation().model().integration.dt);
        os_ << "simulated " << std::setprecision(4) << simulated << " s in " << seconds
            << " s of wall time: real-time factor " << simulated / std::max(seconds, 1e-12)
            << " (a batch run is not paced)\n";
    }
}

}  // namespace bop::app
