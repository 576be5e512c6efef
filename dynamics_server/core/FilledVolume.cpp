#include "FilledVolume.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace bop::core {

double filledVoxels(const Dims& d, double h, const std::vector<Eigen::Vector3d>& pos,
                    const std::vector<Eigen::Vector3d>& normal, double reach) {
    const std::size_t n = d.count();
    enum : std::uint8_t { Far = 0, NearIn = 1, NearOut = 2, Outside = 3 };
    std::vector<std::uint8_t> state(n, Far);
    std::vector<float> best(n, std::numeric_limits<float>::infinity());
    const int r = int(std::ceil(reach / h)) + 1;
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const Eigen::Vector3i c = (pos[i] / h).array().floor().cast<int>().matrix();
        for (int z = std::max(0, c.z() - r); z <= std::min(d.nz - 1, c.z() + r); ++z)
            for (int y = std::max(0, c.y() - r); y <= std::min(d.ny - 1, c.y() + r); ++y)
                for (int x = std::max(0, c.x() - r); x <= std::min(d.nx - 1, c.x() + r); ++x) {
                    const Eigen::Vector3d centre = (Eigen::Vector3d(x, y, z).array() + 0.5) * h;
                    const double d2 = (centre - pos[i]).squaredNorm();
                    const std::size_t v = d.index(x, y, z);
                    if (d2 > reach * reach || d2 >= best[v]) continue;
                    best[v] = float(d2);
                    state[v] = (centre - pos[i]).dot(normal[i]) < 0.5 * h ? NearIn : NearOut;
                }
    }
    // Flood the outside from the border through every voxel not inside the sheet.
    std::vector<std::size_t> stack;
    auto visit = [&](int x, int y, int z) {
        const std::size_t v = d.index(x, y, z);
        if (state[v] == Far || state[v] == NearOut) {
            state[v] = Outside;
            stack.push_back(v);
        }
    };
    for (int z = 0; z < d.nz; ++z)
        for (int y = 0; y < d.ny; ++y)
            for (int x = 0; x < d.nx; ++x)
                if (x == 0 || y == 0 || z == 0 || x == d.nx - 1 || y == d.ny - 1 || z == d.nz - 1) visit(x, y, z);
    while (!stack.empty()) {
        const Eigen::Vector3i c = d.coords(stack.back());
        stack.pop_back();
        static const int step[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (const auto& s : step) {
            const Eigen::Vector3i q = c + Eigen::Vector3i(s[0], s[1], s[2]);
            if (d.contains(q.x(), q.y(), q.z())) visit(q.x(), q.y(), q.z());
        }
    }
    double inside = 0;
    for (std::uint8_t s : state) inside += s == NearIn || s == Far;
    return inside;
}

}  // namespace bop::core
