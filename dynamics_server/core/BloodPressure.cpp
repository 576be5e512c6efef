#include "BloodPressure.hpp"

#include "Threads.hpp"

namespace bop::core {

BloodSums bloodSums(const Model& model, const Particles& p) {
    BloodSums s;  // on the threads, in fixed blocks
    s.mv2 = sumIndex(p.size(), [&](std::size_t i) {
        return model.isSurface(p.species[i]) ? 0.0 : p.vel[i].squaredNorm();  // unit mass
    });
    s.count = sumIndex(p.size(), [&](std::size_t i) { return model.isSurface(p.species[i]) ? 0.0 : 1.0; });
    return s;
}

}  // namespace bop::core
