#include "Thickness.hpp"

#include "bop/common/DistanceTransform.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace bop::shape {

ThinParts findThinParts(const GradientMap& map, int bag, double minimumVoxels, std::vector<char>* mask) {
    const Dims& d = map.dims();
    std::vector<std::int32_t> feature(map.occ.size()), dist2;
    ThinParts out;
    for (std::size_t v = 0; v < map.occ.size(); ++v) {
        const bool in = map.inBag(v, bag);  // this bag's voxels and those of the bags inside it
        feature[v] = in ? kNoSite : 0;
        out.bagVoxels += in;
    }
    if (out.bagVoxels == 0) return out;
    exactDistanceTransform(d, feature, dist2, 1);
    // Voxels beyond the grid count as outside: a bag that touches its edge is cut there.
    const auto depth2 = [&](int x, int y, int z) -> std::int64_t {
        if (!d.contains(x, y, z)) return 0;
        const std::int64_t e = std::min({x + 1, y + 1, z + 1, d.nx - x, d.ny - y, d.nz - z});
        return std::min<std::int64_t>(dist2[d.index(x, y, z)], e * e);
    };
    std::vector<char> thin(map.occ.size(), 0);
    out.thinnestVoxels = std::numeric_limits<double>::infinity();
    for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
            for (int x = 0; x < d.nx; ++x) {
                if (!map.inBag(d.index(x, y, z), bag)) continue;
                const std::int64_t r2 = depth2(x, y, z);
                bool ridge = true;
                for (int k = -1; k <= 1 && ridge; ++k)
                    for (int j = -1; j <= 1 && ridge; ++j)
                        for (int i = -1; i <= 1 && ridge; ++i) ridge = depth2(x + i, y + j, z + k) <= r2;
                if (!ridge) continue;
                const double across = 2 * std::sqrt(double(r2)) - 1;
                out.thinnestVoxels = std::min(out.thinnestVoxels, across);
                if (across >= minimumVoxels) continue;
                const int r = int(std::ceil(std::sqrt(double(r2))));
                for (int k = -r; k <= r; ++k)
                    for (int j = -r; j <= r; ++j)
                        for (int i = -r; i <= r; ++i) {
                            if (std::int64_t(i * i + j * j + k * k) >= r2 || !d.contains(x + i, y + j, z + k)) continue;
                            const std::size_t w = d.index(x + i, y + j, z + k);
                            if (map.inBag(w, bag)) thin[w] = 1;
                        }
            }
    out.thinVoxels = std::size_t(std::count(thin.begin(), thin.end(), char(1)));
    if (mask)
        for (std::size_t v = 0; v < thin.size(); ++v) (*mask)[v] |= thin[v];
    return out;
}

std::string thinPartsWarning(const std::string& bagName, const ThinParts& t, double r0Voxels) {
    if (t.thinVoxels == 0) return "";
    char text[512];
    std::snprintf(text, sizeof text,
                  "bag '%s': %zu of its %zu voxels (%.1f%%) lie in parts thinner than 2 r0 (%.3g voxels), too thin "
                  "for two sheets of surface particles and a volume; the thinnest is %.3g voxels across (%.2f r0): "
                  "r0_voxels = %.3g would hold it (or a finer grid)",
                  bagName.c_str(), t.thinVoxels, t.bagVoxels, 100.0 * double(t.thinVoxels) / double(t.bagVoxels),
                  2 * r0Voxels, t.thinnestVoxels, t.thinnestVoxels / r0Voxels, std::max(0.1, t.thinnestVoxels / 2));
    return text;
}

std::vector<std::string> thinPartsWarnings(const GradientMap& map, const std::vector<std::string>& bagNames,
                                           std::vector<char>* membrane) {
    std::vector<std::string> out;
    if (membrane) membrane->assign(map.occ.size(), 0);
    for (std::size_t b = 0; b < bagNames.size(); ++b) {
        std::string w =
            thinPartsWarning(bagNames[b], findThinParts(map, int(b) + 1, 2 * map.r0Voxels, membrane), map.r0Voxels);
        if (!w.empty()) out.push_back(std::move(w));
    }
    return out;
}

}  // namespace bop::shape
