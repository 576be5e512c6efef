#include "Labels.hpp"

#include "bop/common/GradientMap.hpp"

namespace bop::shape {

std::vector<std::uint8_t> labelVoxels(const BagLayout& bags) {
    const Dims& d = bags.bag.dims;
    std::vector<std::uint8_t> occ(d.count(), 0);
    static constexpr int kOff[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
#pragma omp parallel for schedule(static)
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const int bag = bags.bag(i, j, k);
                if (bag == 0) continue;
                bool surface = false;
                for (const auto& o : kOff) {
                    const int a = i + o[0], b = j + o[1], c = k + o[2];
                    // the border counts as outside
                    surface = surface || !d.contains(a, b, c) || !bags.within(bags.bag(a, b, c), bag);
                }
                occ[d.index(i, j, k)] = std::uint8_t(surface ? surfaceSpeciesOfBag(bag) : volumeSpeciesOfBag(bag));
            }
    return occ;
}

}  // namespace bop::shape
