#include "app/runs/BatchReport.hpp"

#include <iomanip>

namespace bop::app {

std::pair<std::size_t, std::size_t> countKinds(const core::Model& model, const core::Particles& p) {
    std::size_t surface = 0, volume = 0;
    for (auto s : p.species) (model.isSurface(s) ? surface : volume)++;
    return {surface, volume};
}

void BatchReport::progress(const core::Simulation& sim, long long done, long long total,
                           std::chrono::steady_clock::time_point start) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto [surface, volume] = countKinds(model_, sim.particles());
    const auto& st = sim.stats();
    os_ << std::fixed << std::setprecision(1) << "step " << st.step << " (" << 100.0 * double(done) / double(total)
        << "%)  particles " << surface << " surface + " << volume << " volume  E_kin " << std::setprecision(4)
        << st.kinetic << "  E_pair " << st.forces.pairEnergy << "  " << std::setprecision(1)
        << double(done) / std::max(t, 1e-9) << " steps/s" << std::endl;
}

void BatchReport::summary(const core::Simulation& sim, long long steps, double seconds) {
    const auto [surface, volume] = countKinds(model_, sim.particles());
    const core::StepTimes& t = sim.times();
    const double total = std::max(t.total(), 1e-12);
    const double perStep = steps > 0 ? 1e3 / double(steps) : 0.0;
    os_ << "\nphase          ms/step   share\n" << std::fixed;
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
    const core::NeighbourList& list = sim.forceField().neighbours();
    const auto perPair = [](double seconds, double pairs) { return pairs > 0 ? seconds / pairs * 1e9 : 0.0; };
    os_ << "pair loops (CPU time over threads): " << std::setprecision(1)
        << perPair(t.forces.ljLoopSeconds, t.forces.ljPairs) << " ns per LJ pair in range, "
        << perPair(t.forces.orientedLoopSeconds, t.forces.orientedPairs) << " ns per oriented pair in range\n";
    const core::ForceStats& f = sim.stats().forces;
    os_ << "neighbour list: built " << list.builds() << " times (set-up included), " << list.pairCount()
        << " LJ pairs within its cutoff + skin (" << f.pairsInRange << " within the cutoff), " << list.widePairCount()
        << " oriented pairs within theirs (" << f.orientedPairsInRange << "), " << list.ghostCount()
        << " periodic images\n";
    const core::ForceField& field = sim.forceField();
    if (field.pruneSkin() > 0)
        os_ << "pair loops read the list pruned to each cutoff + " << std::setprecision(3)
            << field.pruneSkin() / core::kR0 << " r0: pruned " << field.pruned().prunes() << " times, "
            << field.pruned().pairCount() << " LJ and " << field.pruned().widePairCount()
            << " oriented pairs at the last\n";
    const double rate = double(steps) / std::max(seconds, 1e-12);
    os_ << "\n            Surface  Volume   Total   steps/s   particle-steps/s\n"
        << "this run  " << std::setw(9) << surface << std::setw(8) << volume << std::setw(8) << surface + volume
        << std::setw(10) << std::setprecision(1) << rate << std::setw(19) << std::setprecision(0)
        << rate * double(surface + volume) << "\n";
    const auto& c = sim.construction().totals();
    os_ << "births " << c.births << ", deaths " << c.deaths << "; E_kin " << std::setprecision(5) << sim.stats().kinetic
        << ", E_pair " << sim.stats().forces.pairEnergy << ", virial " << sim.stats().forces.virial << "\n";
}

}  // namespace bop::app
