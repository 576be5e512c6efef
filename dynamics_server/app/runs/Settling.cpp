#include "app/runs/Settling.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace bop::app {

Settling::Settling(core::Run& run, const RunSettings& s, const std::string& from, const std::string& file)
    : watch_(s.settleKinetic, s.settleEverySteps, s.settleCalmSteps),
      maxSteps_(s.settleFire ? s.settleFire->maxSteps : 0) {
    if (from.empty()) {
        if (s.settleFire) run.minimise(s.settleFire);
        return;
    }
    std::istringstream in(from);
    std::string phase;
    long long calm = -1;
    core::FireState f;
    in >> phase >> calm;
    const bool fire = phase == "fire" && s.settleFire && (in >> f.dt >> f.alpha >> f.steps >> f.sincePositive) &&
                      f.dt > 0 && f.alpha >= 0 && f.steps >= 0 && f.sincePositive >= 0;
    const bool dynamics = phase == "dynamics" && (in >> minimiserSteps_) && minimiserSteps_ >= 0;
    std::string rest;
    if (calm < 0 || !(fire || dynamics) || (in >> rest))
        throw Error(file, "Settle=\"" + from +
                              "\": expected \"fire CALM DT ALPHA STEPS SINCE\" (a scene settled by the minimiser) or "
                              "\"dynamics CALM FIRE_STEPS\"");
    watch_.resume(calm < watch_.checksNeeded() ? calm : 0);  // a settled state is checked again
    if (fire) run.minimise(s.settleFire, f);
}

bool Settling::afterStep(core::Run& run) {
    if (watch_.settled() || !watch_.due(run.stepNumber())) return watch_.settled();
    const core::Totals t = run.totals();  // the same on every process
    last_ = t.kinetic / std::max(1.0, t.particles);
    const bool calm = watch_.observe(last_);
    if (!run.minimising()) return calm;
    const long long steps = run.minimiserState()->steps;
    if (!calm && steps < maxSteps_) return false;
    // Calm under the minimiser, or at its most steps: the damped dynamics, from rest, must find it calm.
    minimiserSteps_ = steps;
    run.minimise(std::nullopt);
    watch_.resume(0);
    return false;
}

std::string Settling::state(const core::Run& run) const {
    char text[160];
    if (const auto f = run.minimiserState())
        std::snprintf(text, sizeof text, "fire %lld %.17g %.17g %lld %lld", watch_.calmChecks(), f->dt, f->alpha,
                      f->steps, f->sincePositive);
    else
        std::snprintf(text, sizeof text, "dynamics %lld %lld", watch_.calmChecks(), minimiserSteps_);
    return text;
}

}  // namespace bop::app
