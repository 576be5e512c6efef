#include "BagLayout.hpp"

#include "ShapeSpec.hpp"
#include "bop/common/Error.hpp"

#include <algorithm>
#include <string>

namespace bop::shape {
namespace {

// Whether some face neighbour of (i, j, k), or the grid's border, lies outside bag b.
bool touchesOutside(const BagLayout& l, int i, int j, int k, int b) {
    static constexpr int kOff[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (const auto& o : kOff) {
        const int x = i + o[0], y = j + o[1], z = k + o[2];
        if (!l.bag.dims.contains(x, y, z) || !l.within(l.bag(x, y, z), b)) return true;
    }
    return false;
}

}  // namespace

BagLayout BagLayout::nested(const Volume<std::uint8_t>& depth) {
    BagLayout l;
    l.bag = depth;
    int bags = 1;
    for (auto d : depth.data) bags = std::max(bags, int(d));
    l.parent.resize(std::size_t(bags) + 1);
    for (int b = 1; b <= bags; ++b) l.parent[std::size_t(b)] = std::uint8_t(b - 1);
    return l;
}

BagLayout arrangeBags(const ShapeSpec& spec, const std::vector<Mask>& masks, int frame) {
    const std::size_t n = masks.size();
    if (n > std::size_t(kMaxBags))
        throw Error(spec.sceneFile, "key 'shape.bag': " + std::to_string(n) + " bags, at most " +
                                        std::to_string(kMaxBags) + " fit the species numbers");
    const Dims d = masks.front().dims;
    const std::string at = n > 1 || frame > 0 ? " (frame " + std::to_string(frame) + ")" : "";
    const auto fail = [&](std::size_t b, const std::string& what) {
        throw Error(spec.sceneFile, "key '" + spec.bags[b].key + "': bag '" + spec.bags[b].name + "' " + what + at);
    };
    // Voxels of each bag and of each pair's overlap.
    std::vector<std::size_t> count(n, 0), overlap(n * n, 0);
    std::vector<std::size_t> holding;
    for (std::size_t v = 0; v < d.count(); ++v) {
        holding.clear();
        for (std::size_t b = 0; b < n; ++b)
            if (masks[b].data[v]) holding.push_back(b);
        for (std::size_t a : holding) {
            ++count[a];
            for (std::size_t b : holding) overlap[a * n + b] += a != b;
        }
    }
    for (std::size_t b = 0; b < n; ++b)
        if (count[b] == 0)
            fail(b, "(" + spec.bags[b].source->describe() +
                        ") has no object voxels on the grid; expected a non-empty bitmap (check its size against "
                        "voxel_size_mm)");
    // The bag around each bag: the smallest of those that hold all of it.
    BagLayout l;
    l.parent.assign(n + 1, 0);
    for (std::size_t a = 0; a < n; ++a)
        for (std::size_t b = 0; b < n; ++b) {
            const std::size_t both = overlap[a * n + b];
            if (a == b || both == 0) continue;
            // Each pair's errors name the bag listed later.
            if (a > b && both == count[a] && both == count[b])
                fail(a, "holds the same voxels as bag '" + spec.bags[b].name + "'; expected distinct bags");
            if (a > b && both < count[a] && both < count[b])
                fail(a, "and bag '" + spec.bags[b].name + "' overlap in " + std::to_string(both) + " voxels, and " +
                            std::to_string(count[a] - both) + " voxels of bag '" + spec.bags[a].name +
                            "' lie outside bag '" + spec.bags[b].name +
                            "'; bags lie side by side, touch, or one lies inside another");
            const std::size_t p = l.parent[a + 1];
            if (both == count[a] && (p == 0 || count[b] < count[p - 1])) l.parent[a + 1] = std::uint8_t(b + 1);
        }
    // Each voxel to the innermost bag holding it: the smallest.
    l.bag = Volume<std::uint8_t>(d, 0);
    for (std::size_t v = 0; v < d.count(); ++v) {
        std::size_t best = 0;
        for (std::size_t b = 0; b < n; ++b)
            if (masks[b].data[v] && (best == 0 || count[b] < count[best - 1])) best = b + 1;
        l.bag.data[v] = std::uint8_t(best);
    }
    for (std::size_t b = 0; b < n; ++b) {
        const int around = l.parent[b + 1];
        if (around == 0) continue;
        std::size_t touching = 0;
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i)
                    if (masks[b](i, j, k) && touchesOutside(l, i, j, k, around)) ++touching;
        if (touching)
            fail(b, "touches the outside of bag '" + spec.bags[std::size_t(around) - 1].name + "' at " +
                        std::to_string(touching) +
                        " voxels; a bag inside another must lie strictly inside its surface");
    }
    return l;
}

}  // namespace bop::shape
