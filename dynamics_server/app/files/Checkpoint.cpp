#include "app/files/Checkpoint.hpp"

#include "app/scene/RunStart.hpp"
#include "bop/common/Npy.hpp"  // writeFileAtomic

#include <ostream>

namespace bop::app {

XyzFrameInfo snapshotInfo(const core::Model& model, long long step) {
    XyzFrameInfo info;
    info.step = step;
    info.time = double(step) * model.integration.dt;
    info.units = model.units;
    info.boxLo = model.box.lo;
    info.boxHi = model.box.hi;
    info.periodic = model.box.periodic;
    return info;
}

void writeCheckpoint(const std::string& path, const core::Particles& all, const core::Model& model,
                     const core::Construction& construction, long long step, const std::string& settle,
                     const std::vector<core::CutCommand>& cuts, const std::vector<std::vector<std::uint64_t>>& yields) {
    XyzFrameInfo info = snapshotInfo(model, step);
    info.births.assign(construction.birthSwitches().begin() + 1, construction.birthSwitches().end());
    info.seeds = static_cast<long long>(construction.seedCount());
    info.nextId = static_cast<long long>(construction.nextId());
    info.settle = settle;
    info.cuts = cuts;
    info.yields = yields;
    writeFileAtomic(path, [&](std::ostream& os) { writeExtendedXyz(os, all, speciesNames(model), info); });
}

}  // namespace bop::app
