// bop-shape's report per bag: its voxels and volume, the bag holding it, the bags inside it, and
// the bags it touches (with the faces they share), as text and as bags.csv.
#include "app/tools/ShapeReport.hpp"
#include "bop/common/Error.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>

namespace bop::app {

std::vector<BagSummary> summariseBags(const GradientMap& m, const std::vector<std::string>& names) {
    std::vector<BagSummary> bags(std::size_t(m.bagCount));
    for (int b = 1; b <= m.bagCount; ++b) {
        BagSummary& s = bags[std::size_t(b - 1)];
        s.bag = b;
        s.name = std::size_t(b - 1) < names.size() ? names[std::size_t(b - 1)] : "bag " + std::to_string(b);
        s.parent = m.parentBag(b);
    }
    const Dims& d = m.dims();
    std::map<std::pair<int, int>, std::size_t> faces;  // (a, b), a < b: faces shared by unrelated bags
    for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
            for (int x = 0; x < d.nx; ++x) {
                const std::size_t v = d.index(x, y, z);
                const int a = bagOfSpecies(m.occ[v]);
                if (a == 0) continue;
                BagSummary& s = bags[std::size_t(a - 1)];
                ++(isSurfaceSpecies(m.occ[v]) ? s.surfaceVoxels : s.volumeVoxels);
                const int next[3][3] = {{x + 1, y, z}, {x, y + 1, z}, {x, y, z + 1}};
                for (const auto& n : next) {
                    if (!d.contains(n[0], n[1], n[2])) continue;
                    const int b = bagOfSpecies(m.occ[d.index(n[0], n[1], n[2])]);
                    if (b == 0 || b == a || m.bagWithin(a, b) || m.bagWithin(b, a)) continue;
                    ++faces[{std::min(a, b), std::max(a, b)}];
                }
            }
    for (const auto& [ab, n] : faces) {
        bags[std::size_t(ab.first - 1)].touching.push_back({ab.second, n});
        bags[std::size_t(ab.second - 1)].touching.push_back({ab.first, n});
    }
    const double mlPerVoxel = std::pow(m.grid.voxelMm, 3) / 1000.0;
    for (BagSummary& s : bags) s.volumeMl = double(s.surfaceVoxels + s.volumeVoxels) * mlPerVoxel;
    return bags;
}

void printBagReport(std::ostream& os, const std::vector<BagSummary>& bags) {
    auto name = [&](int b) { return b ? "'" + bags[std::size_t(b - 1)].name + "'" : std::string("none"); };
    os << std::fixed << std::setprecision(3);
    for (const BagSummary& s : bags) {
        os << "bag '" << s.name << "'  " << s.surfaceVoxels << " surface + " << s.volumeVoxels << " volume voxels ("
           << s.volumeMl << " mL); inside " << name(s.parent);
        std::string holds;
        for (const BagSummary& t : bags)
            if (t.parent == s.bag) holds += (holds.empty() ? "" : ", ") + name(t.bag);
        os << "; holds " << (holds.empty() ? "none" : holds) << "; touches ";
        if (s.touching.empty()) os << "none";
        for (std::size_t i = 0; i < s.touching.size(); ++i)
            os << (i ? ", " : "") << name(s.touching[i].first) << " (" << s.touching[i].second << " faces)";
        os << "\n";
    }
}

void writeBagsCsv(const std::string& path, const std::vector<BagSummary>& bags) {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the bag table");
    out << "bag,name,surface_voxels,volume_voxels,volume_ml,inside_bag,touching_bags,shared_faces\n";
    for (const BagSummary& s : bags) {
        std::string touching, shared;
        for (const auto& [b, n] : s.touching) {
            touching += (touching.empty() ? "" : " ") + std::to_string(b);
            shared += (shared.empty() ? "" : " ") + std::to_string(n);
        }
        out << s.bag << ",\"" << s.name << "\"," << s.surfaceVoxels << "," << s.volumeVoxels << ","
            << std::setprecision(6) << s.volumeMl << "," << s.parent << "," << touching << "," << shared << "\n";
    }
    if (!out) throw Error(path, "write failed");
}

}  // namespace bop::app
