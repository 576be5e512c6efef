#include "BloodPressure.hpp"

namespace bop::core {

BloodSums bloodSums(const Model& model, const Particles& p) {
    BloodSums s;
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (model.isSurface(p.species[i])) continue;
        s.mv2 += p.vel[i].squaredNorm();  // unit mass
        s.count += 1;
    }
    return s;
}

}  // namespace bop::core
