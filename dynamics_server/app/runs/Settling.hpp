#pragma once
// A placed bag's settling (docs/physics.md §7.5), the same in a batch run and the tests, by the
// SettleWatch rule on the kinetic energy per particle. With the minimiser (core/Fire.hpp, the
// default), it steps first until the rule holds under it (or for at most FireParams::maxSteps);
// then the damped dynamics, from rest, steps until the rule holds again: the bag is settled when
// today's dynamics says so.
//
// Its state goes into checkpoints (Settle=, docs/file-formats.md), so that a run restarted from
// one settles as the uninterrupted run does: "fire CALM DT ALPHA STEPS SINCE" (the calm checks in
// a row so far and core::FireState) or "dynamics CALM FIRE_STEPS". A restart from a settled
// state checks it again.
#include "app/runs/SettleWatch.hpp"
#include "app/scene/SceneConfig.hpp"
#include "core/Run.hpp"

#include <string>

namespace bop::app {

class Settling {
public:
    // Starts the minimiser on `run` when the scene settles by it, or goes on from `from`, a
    // checkpoint's state (bop::Error naming `file` when it is not one). Collective.
    Settling(core::Run& run, const RunSettings& settings, const std::string& from = {}, const std::string& file = {});
    // After each step: a check when one is due; true once settled. Collective.
    bool afterStep(core::Run& run);
    bool settled() const { return watch_.settled(); }
    double lastPerParticle() const { return last_; }  // the last check's kinetic energy per particle, epsilon
    long long everySteps() const { return watch_.everySteps(); }
    long long minimiserSteps() const { return minimiserSteps_; }  // steps taken by the minimiser (0: none)
    std::string state(const core::Run& run) const;                // for a checkpoint's Settle=

private:
    SettleWatch watch_;
    double last_ = 0;
    long long minimiserSteps_ = 0;
    long long maxSteps_;  // the minimiser's most steps (FireParams::maxSteps)
};

}  // namespace bop::app
