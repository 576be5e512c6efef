#include "app/scene/Fidelity.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>

namespace bop::app {

void printFidelity(std::ostream& out, const Fidelity& f) {
    out << "shape fidelity: " << std::setprecision(3) << 100 * f.surfaceInOwnVoxels
        << "% of surface particles in their surface voxels, " << 100 * f.volumeInOwnVoxels
        << "% of volume particles in their volume voxels, median normal angle " << std::setprecision(2)
        << f.medianNormalAngleDeg << " deg\n"
        << std::setprecision(6);
    for (const BagFidelity& b : f.bags)
        out << "  bag '" << b.name << "': " << std::setprecision(3) << 100 * b.surfaceInOwnVoxels << "% of its "
            << b.surface << " surface particles in its surface voxels, " << 100 * b.volumeInOwnVoxels << "% of its "
            << b.volume << " volume particles in its volume voxels, " << std::setprecision(4) << 100 * b.insideBag
            << "% of its particles inside it, median normal angle " << std::setprecision(2) << b.medianNormalAngleDeg
            << " deg\n"
            << std::setprecision(6);
}

namespace {

double median(std::vector<double>& v) {  // 0 for none; the upper one of an even count
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

Fidelity measureFidelity(const core::Model& model, const GradientMap& m, const core::Particles& p) {
    Fidelity f;
    const double h = voxelLength(m.r0Voxels);
    std::size_t surfaceIn = 0, volumeIn = 0;
    std::vector<double> angles;
    std::vector<std::vector<double>> bagAngles;  // per bag
    // Every bag, one alone too (its particles inside it): its surface and volume species 2k - 1, 2k.
    const int bags = model.hasSurfaceSpecies() ? std::min(m.bagCount, (model.speciesCount() + 1) / 2) : 0;
    std::vector<std::size_t> ownSurface(std::size_t(bags) + 1, 0), ownVolume(std::size_t(bags) + 1, 0),
        inside(std::size_t(bags) + 1, 0);
    f.bags.resize(std::size_t(bags));
    bagAngles.resize(std::size_t(bags) + 1);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::int64_t voxel = m.voxelHolding(p.pos[i] / h);
        const bool inGrid = voxel >= 0;
        const std::size_t idx = inGrid ? std::size_t(voxel) : 0;
        const bool own = inGrid && m.occ[idx] == p.species[i];
        if (const int bag = bagOfSpecies(p.species[i]); bag <= bags) {
            BagFidelity& b = f.bags[std::size_t(bag) - 1];
            const bool surface = model.isSurface(p.species[i]);
            (surface ? b.surface : b.volume) += 1;
            (surface ? ownSurface : ownVolume)[std::size_t(bag)] += own;
            inside[std::size_t(bag)] += inGrid && bagOfSpecies(m.occ[idx]) == bag;
        }
        if (model.isSurface(p.species[i])) {
            ++f.surface;
            surfaceIn += own;
            if (inGrid) {
                const double cosA = std::clamp(p.normal[i].dot(m.nearestSurface(idx).normal.cast<double>()), -1.0, 1.0);
                angles.push_back(std::acos(cosA) * 180.0 / M_PI);
                if (const int bag = bagOfSpecies(p.species[i]); bag <= bags)
                    bagAngles[std::size_t(bag)].push_back(angles.back());
            }
        } else {
            ++f.volume;
            volumeIn += own;
        }
    }
    f.surfaceInOwnVoxels = f.surface ? double(surfaceIn) / double(f.surface) : 0;
    f.volumeInOwnVoxels = f.volume ? double(volumeIn) / double(f.volume) : 0;
    for (int bag = 1; bag <= bags; ++bag) {
        BagFidelity& b = f.bags[std::size_t(bag) - 1];
        b.name = model.species[std::size_t(surfaceSpeciesOfBag(bag))].name;
        if (b.name.size() > 8 && b.name.ends_with("-surface")) b.name.resize(b.name.size() - 8);
        b.surfaceInOwnVoxels = b.surface ? double(ownSurface[std::size_t(bag)]) / double(b.surface) : 0;
        b.volumeInOwnVoxels = b.volume ? double(ownVolume[std::size_t(bag)]) / double(b.volume) : 0;
        b.insideBag = b.surface + b.volume ? double(inside[std::size_t(bag)]) / double(b.surface + b.volume) : 0;
    }
    f.medianNormalAngleDeg = median(angles);
    for (int bag = 1; bag <= bags; ++bag)
        f.bags[std::size_t(bag) - 1].medianNormalAngleDeg = median(bagAngles[std::size_t(bag)]);
    return f;
}

}  // namespace bop::app
