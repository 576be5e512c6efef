#include "app/files/Checkpoint.hpp"

#include "app/scene/SimulationSetup.hpp"
#include "bop/common/Npy.hpp"  // writeFileAtomic

#include <sstream>

namespace bop::app {

XyzFrameInfo snapshotInfo(const core::Model& model, long long step) {
    XyzFrameInfo info;
    info.step = step;
    info.time = double(step) * model.integration.dt;
    info.boxLo = model.box.lo;
    info.boxHi = model.box.hi;
    info.periodic = model.box.periodic;
    return info;
}

void writeCheckpoint(const std::string& path, const core::Particles& all, const core::Model& model,
                     const core::Construction& construction, long long step) {
    XyzFrameInfo info = snapshotInfo(model, step);
    info.births.assign(construction.birthSwitches().begin() + 1, construction.birthSwitches().end());
    info.seeds = static_cast<long long>(construction.seedCount());
    info.nextId = static_cast<long long>(construction.nextId());
    std::ostringstream text;
    writeExtendedXyz(text, all, speciesNames(model), info);
    const std::string s = text.str();
    writeFileAtomic(path, s.data(), s.size());
}

}  // namespace bop::app
