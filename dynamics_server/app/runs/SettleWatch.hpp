#pragma once
// When a bag built by placement has settled (docs/physics.md §7.5): the mean kinetic energy per
// particle at or below `kinetic` at every check over `calmSteps` steps, the checks
// `everySteps` steps apart. Checks close together end the run soon after the bag calms down;
// the span keeps a passing dip of the kinetic energy from ending it.
namespace bop::app {

class SettleWatch {
public:
    // kinetic: energy units (epsilon) per particle; everySteps >= 1; calmSteps >= 0.
    SettleWatch(double kinetic, long long everySteps, long long calmSteps)
        : kinetic_(kinetic), every_(everySteps), calmSteps_(calmSteps) {}

    bool due(long long step) const { return step % every_ == 0; }
    // One check's mean kinetic energy per particle (energy units); true once settled.
    bool observe(double perParticle) {
        calm_ = perParticle <= kinetic_ ? calm_ + 1 : 0;
        return settled();
    }
    bool settled() const { return calm_ >= checksNeeded(); }
    long long calmChecks() const { return calm_; }             // calm checks in a row so far
    void resume(long long calmChecks) { calm_ = calmChecks; }  // from a checkpoint's count (0: afresh)
    // Calm checks in a row that span calmSteps: 1 + ceil(calmSteps / everySteps).
    long long checksNeeded() const { return 1 + (calmSteps_ + every_ - 1) / every_; }
    long long everySteps() const { return every_; }

private:
    double kinetic_;
    long long every_, calmSteps_;
    long long calm_ = 0;  // calm checks in a row so far
};

}  // namespace bop::app
