#include "Labels.hpp"

#include "bop/common/GradientMap.hpp"

namespace bop::shape {

bool touchesBelow(const Volume<std::uint8_t>& depth, int i, int j, int k, int level) {
    static constexpr int kOff[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (const auto& o : kOff) {
        const int a = i + o[0], b = j + o[1], c = k + o[2];
        if (!depth.dims.contains(a, b, c)) return true;  // the border counts as outside
        if (depth(a, b, c) < level) return true;
    }
    return false;
}

std::vector<std::uint8_t> labelVoxels(const Volume<std::uint8_t>& depth) {
    const Dims& d = depth.dims;
    std::vector<std::uint8_t> occ(d.count(), 0);
#pragma omp parallel for schedule(static)
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const int bag = depth(i, j, k);
                if (bag == 0) continue;
                const bool surface = touchesBelow(depth, i, j, k, bag);
                occ[d.index(i, j, k)] = std::uint8_t(surface ? surfaceSpeciesOfBag(bag) : volumeSpeciesOfBag(bag));
            }
    return occ;
}

}  // namespace bop::shape
