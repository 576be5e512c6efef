#include "scene/SyntheticBag.hpp"

#include <cmath>
#include <numbers>

namespace bop::viz {

protocol::StateFrame torusBag(double R, double a, double r0) {
    protocol::StateFrame f;
    const double pi = std::numbers::pi;
    const int rings = int(std::round(2 * pi * a / r0));
    for (int j = 0; j < rings; ++j) {
        const double v = 2 * pi * j / rings;
        const int around = int(std::round(2 * pi * (R + a * std::cos(v)) / r0));
        for (int k = 0; k < around; ++k) {
            const double u = 2 * pi * (k + 0.5 * (j % 2)) / around;
            const Eigen::Vector3d n(std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v));
            const Eigen::Vector3d x = Eigen::Vector3d(R * std::cos(u), R * std::sin(u), 0) + a * n;
            f.positions.insert(f.positions.end(), {float(x.x()), float(x.y()), float(x.z())});
            f.normals.insert(f.normals.end(), {float(n.x()), float(n.y()), float(n.z())});
            f.species.push_back(1);
        }
    }
    const int half = int(std::ceil((R + a) / r0));
    for (int i = -half; i <= half; ++i)
        for (int j = -half; j <= half; ++j)
            for (int k = -half; k <= half; ++k) {
                const Eigen::Vector3d x = r0 * Eigen::Vector3d(i, j, k);
                if (std::hypot(std::hypot(x.x(), x.y()) - R, x.z()) > a - 0.8 * r0) continue;
                f.positions.insert(f.positions.end(), {float(x.x()), float(x.y()), float(x.z())});
                f.normals.insert(f.normals.end(), {0.0f, 0.0f, 1.0f});
                f.species.push_back(2);
            }
    f.frameParticleCount = std::uint32_t(f.species.size());
    return f;
}

protocol::SceneInfo torusBagScene(double R, double a, double r0, const std::array<std::uint8_t, 4>& surfaceRgba,
                                  const std::array<std::uint8_t, 4>& volumeRgba) {
    protocol::SceneInfo s;
    s.species = {{"membrane", protocol::SpeciesKind::Surface, surfaceRgba},
                 {"fill", protocol::SpeciesKind::Volume, volumeRgba}};
    s.boxLo = Eigen::Vector3d(-(R + a), -(R + a), -a);
    s.boxHi = Eigen::Vector3d(R + a, R + a, a);
    s.r0 = r0;
    return s;
}

}  // namespace bop::viz
