#include "scene/Instances.hpp"

#include <cmath>

namespace bop::viz {

std::uint32_t packRgba(const std::array<std::uint8_t, 4>& c) {
    return std::uint32_t(c[0]) | std::uint32_t(c[1]) << 8 | std::uint32_t(c[2]) << 16 | std::uint32_t(c[3]) << 24;
}

void buildInstances(const protocol::StateFrame& f, const protocol::SceneInfo& s, const ViewFilter& view,
                    Instances& out) {
    out.surfels.clear();
    out.spheres.clear();
    out.cut = out.hidden = out.unknownSpecies = 0;
    out.drawnPerSpecies.assign(s.species.size() + 1, 0);
    const std::size_t n = f.count();
    const bool withNormals = f.normals.size() == 3 * n;
    const float surfelRadius = float(view.surfelRadiusR0 * s.r0), sphereRadius = float(view.sphereRadiusR0 * s.r0);
    std::vector<std::uint32_t> colour(s.species.size() + 1, packRgba(kUnknownSpeciesRgba));
    for (std::size_t k = 0; k < s.species.size(); ++k) colour[k + 1] = packRgba(s.species[k].rgba);
    Eigen::Vector3d cutNormal = Eigen::Vector3d::Zero();
    double cutOffset = 0;
    if (view.cut && view.cut->normal.norm() > 0) {
        cutNormal = view.cut->normal.normalized();
        cutOffset = cutNormal.dot(view.cut->point);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const int sp = f.species[i];
        const bool known = sp >= 1 && std::size_t(sp) <= s.species.size();
        const bool surface = known && s.species[std::size_t(sp) - 1].kind == protocol::SpeciesKind::Surface;
        const bool hiddenSpecies = std::size_t(sp) < view.hiddenSpecies.size() && view.hiddenSpecies[std::size_t(sp)];
        if (hiddenSpecies || (surface ? !view.showSurface : !view.showVolume)) {
            ++out.hidden;
            continue;
        }
        const float* x = &f.positions[3 * i];
        if (cutNormal.dot(Eigen::Vector3d(x[0], x[1], x[2])) > cutOffset) {
            ++out.cut;
            continue;
        }
        const std::uint32_t rgba = known ? colour[std::size_t(sp)] : colour[0];
        if (surface && withNormals) {
            const float* nv = &f.normals[3 * i];
            out.surfels.push_back({{x[0], x[1], x[2]}, {nv[0], nv[1], nv[2]}, surfelRadius, rgba});
        } else {
            out.spheres.push_back({{x[0], x[1], x[2]}, sphereRadius, rgba});
        }
        if (known)
            ++out.drawnPerSpecies[std::size_t(sp)];
        else
            ++out.unknownSpecies;
    }
}

}  // namespace bop::viz

namespace bop::viz {

ProbeMarker probeMarker(const Eigen::Vector3d& p, double reach, double r0, bool active) {
    // Active: warm yellow; off: grey, so that the user sees the probe is not acting.
    const std::uint32_t core = packRgba(active ? std::array<std::uint8_t, 4>{255, 210, 60, 255}
                                               : std::array<std::uint8_t, 4>{150, 150, 150, 255});
    const std::uint32_t halo = packRgba(active ? std::array<std::uint8_t, 4>{255, 210, 60, 64}
                                               : std::array<std::uint8_t, 4>{150, 150, 150, 40});
    const float x = float(p.x()), y = float(p.y()), z = float(p.z());
    return {{{x, y, z}, float(0.3 * r0), core}, {{x, y, z}, float(reach), halo}};
}

}  // namespace bop::viz
