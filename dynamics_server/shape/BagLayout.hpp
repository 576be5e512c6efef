#pragma once
// Where the bags of a shape lie (docs/shape-pipeline.md, "Several bags"): side by side, touching,
// nested, or nested inside one of several. Each voxel belongs to the innermost bag holding it;
// each bag lies directly inside one bag or none (a forest of containment).
#include "bop/common/GradientMap.hpp"
#include "bop/common/Volume.hpp"

#include <cstdint>
#include <vector>

namespace bop::shape {

struct ShapeSpec;

struct BagLayout {
    Volume<std::uint8_t> bag;          // innermost bag holding each voxel, 1..count(); 0 = none
    std::vector<std::uint8_t> parent;  // [b]: the bag holding bag b directly (0: none); [0] unused

    int count() const { return int(parent.size()) - 1; }
    // Whether bag a is bag b or lies inside it (bag 0, outside every bag, lies in none).
    bool within(int a, int b) const { return bagWithin(parent, a, b); }
    // Whether voxel v lies in bag b (in b itself or in a bag inside it).
    bool inside(std::size_t v, int b) const { return within(bag.data[v], b); }

    // The paper's chain from depth(v) = number of nested bags holding v: bag k holds bag k + 1.
    static BagLayout nested(const Volume<std::uint8_t>& depth);
};

// The layout of one mask per bag (in any order): a bag lies inside another when every voxel of
// it does, directly inside the smallest such bag. Throws bop::Error naming the scene file and the
// bag's key for an empty bag, two bags that overlap with neither inside the other, two bags of
// the same voxels, and a bag that touches the outside of the bag around it (it would break that
// bag's surface).
BagLayout arrangeBags(const ShapeSpec& spec, const std::vector<Mask>& masks, int frame);

}  // namespace bop::shape
