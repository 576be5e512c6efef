#pragma once
// How faithfully a built bag takes its shape (the issues' acceptance figures; independent of the
// code that places particles): measured against the whole map the bags were built on.
#include "core/Model.hpp"
#include "core/Particles.hpp"

#include <iosfwd>
#include <string>
#include <vector>

namespace bop::app {

// Shape fidelity of a bag (issue acceptance; independent of the code that places particles):
// fractions of surface particles in voxels of their own species, of volume particles in voxels
// of their own species, and the median angle between a surface particle's normal and the map
// normal at its voxel.
struct BagFidelity {
    std::string name;  // the bag's surface species' name without "-surface"
    std::size_t surface = 0, volume = 0;
    double surfaceInOwnVoxels = 0;    // fraction
    double volumeInOwnVoxels = 0;     // fraction
    double insideBag = 0;             // fraction of the bag's particles in the bag's own voxels (no mixing)
    double medianNormalAngleDeg = 0;  // its surface particles' normals against the map's, degrees
};
struct Fidelity {
    double surfaceInOwnVoxels = 0;    // fraction
    double volumeInOwnVoxels = 0;     // fraction
    double medianNormalAngleDeg = 0;  // degrees
    std::size_t surface = 0, volume = 0;
    std::vector<BagFidelity> bags;  // per bag of the map, one alone too
};
// `map`: the whole map the bags were built on.
Fidelity measureFidelity(const core::Model& model, const GradientMap& map, const core::Particles& p);
// "shape fidelity: ..." as the batch runs' summaries print it, one line, then one line per bag
// ("  bag 'NAME': ...").
void printFidelity(std::ostream& out, const Fidelity& f);

}  // namespace bop::app
