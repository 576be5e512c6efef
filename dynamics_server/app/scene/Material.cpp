#include "app/scene/Material.hpp"

#include "bop/common/Error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace bop::app {
namespace {

std::string format(const char* f, double a, double b = 0, double c = 0, double d = 0) {
    char buf[256];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

}  // namespace

std::vector<Material> readMaterials(const ConfigTable& root, const std::vector<std::string>& bagNames) {
    if (!root.has("material")) return {};
    const std::vector<ConfigTable> tables = root.tableArray("material");
    std::vector<int> owner(bagNames.size(), -1);
    std::vector<Material> given;
    int everyOther = -1;  // the [[material]] without `bags`: every bag no other names
    for (std::size_t t = 0; t < tables.size(); ++t) {
        const ConfigTable& m = tables[t];
        Material mat;
        const auto range = [&](const char* key, double v, double lo, double hi, const char* what) {
            if (!(v > lo && v < hi)) m.fail(key, std::string("expected ") + what + ", got " + std::to_string(v));
            return v;
        };
        mat.youngKpa = range("young_kpa", m.number("young_kpa"), 0, 1e7, "a modulus above 0 kPa");
        mat.poisson = m.number("poisson", mat.poisson);
        if (!(mat.poisson >= 0.25 && mat.poisson < 0.5))
            m.fail("poisson", "expected a ratio from 0.25 (a bonded volume's springs alone) to below 0.5, got " +
                                  std::to_string(mat.poisson));
        mat.densityKgM3 =
            range("density_kg_m3", m.number("density_kg_m3", mat.densityKgM3), 0, 1e5, "a density above 0 kg/m^3");
        mat.relaxationS = range("relaxation_s", m.number("relaxation_s", mat.relaxationS), 0, 1e6, "a time above 0 s");
        mat.shapeHold = m.number("shape_hold", mat.shapeHold);
        if (!(mat.shapeHold >= 0 && mat.shapeHold <= 10))
            m.fail("shape_hold", "expected a fraction of a bond's stiffness from 0 to 10");
        if (m.has("bags")) {
            for (const std::string& name : m.strings("bags")) {
                const auto it = std::find(bagNames.begin(), bagNames.end(), name);
                if (it == bagNames.end()) m.fail("bags", "no bag is named '" + name + "'");
                int& o = owner[std::size_t(it - bagNames.begin())];
                if (o >= 0) m.fail("bags", "bag '" + name + "' already has a material");
                o = int(t);
            }
        } else {
            if (everyOther >= 0) m.fail("bags", "only one [[material]] may leave out `bags` (every other bag)");
            everyOther = int(t);
        }
        mat.name = m.string("name", m.has("bags") ? m.strings("bags").front() : "material" + std::to_string(t + 1));
        m.finish();
        given.push_back(mat);
    }
    std::vector<Material> out;
    for (std::size_t b = 0; b < bagNames.size(); ++b) {
        const int o = owner[b] >= 0 ? owner[b] : everyOther;
        if (o < 0) root.fail("material", "bag '" + bagNames[b] + "' has no material (every bag needs one, or none)");
        out.push_back(given[std::size_t(o)]);
    }
    return out;
}

Calibration calibrate(const std::vector<Material>& materials, double lengthMm, double massScaling) {
    Calibration c;
    c.massScaling = massScaling;
    const auto pWave = [](const Material& m) {  // lambda + 2 mu over E
        return (1 - m.poisson) / ((1 + m.poisson) * (1 - 2 * m.poisson));
    };
    std::size_t stiffest = 0;
    for (std::size_t k = 0; k < materials.size(); ++k)
        if (materials[k].youngKpa * pWave(materials[k]) > materials[stiffest].youngKpa * pWave(materials[stiffest]))
            stiffest = k;
    const Material& top = materials[stiffest];
    const double simPerKpa = kPWaveModulus / (top.youngKpa * pWave(top));  // energy / length^3 per kPa
    const double r0 = bop::kR0;
    for (const Material& m : materials) {
        c.weight.push_back(m.youngKpa * pWave(m) * simPerKpa / kPWaveModulus);
        const double e = m.youngKpa * simPerKpa, mu = e / (2 * (1 + m.poisson));
        const double lambda = 2 * m.poisson * mu / (1 - 2 * m.poisson);
        c.bond.push_back(std::sqrt(2.0) * r0 * mu);  // the springs' lambda = mu = k / (sqrt 2 r0)
        c.bulk.push_back(lambda - mu);
    }
    const double r0M = lengthMm * r0 * 1e-3;
    const double cellM3 = r0M * r0M * r0M / std::sqrt(2.0);  // an fcc site's volume at spacing r0
    const double massKg = materials.front().densityKgM3 * cellM3 * massScaling;
    c.units = UnitSystem::fromModulus(lengthMm, massKg, top.youngKpa * 1e3, top.youngKpa * simPerKpa);
    return c;
}

void applyCalibration(const Calibration& c, const std::vector<Material>& materials, core::Model& model,
                      core::Params& params) {
    const int bags = int(materials.size());
    const auto bagOf = [](int species) { return (species - 1) / 2; };
    const int n = model.speciesCount();
    for (int a = 1; a <= n; ++a)
        for (int b = 1; b <= n; ++b) {
            const int ka = bagOf(a), kb = bagOf(b);
            const double wa = c.weight[std::size_t(ka)], wb = c.weight[std::size_t(kb)];
            // Within a bag the bonds hold; across a border two springs in series.
            params.lj(a, b) = ka == kb ? 0.0 : 2 * wa * wb / (wa + wb);
        }
    for (int k = 0; k < bags; ++k) {
        const Material& m = materials[std::size_t(k)];
        const double w = c.weight[std::size_t(k)], bond = c.bond[std::size_t(k)];
        const int surface = 2 * k + 1, volume = 2 * k + 2;
        params.coNormal(surface, surface) = kSheetWeight * w;
        params.coPlanar(surface, surface) = kSheetWeight * w;
        for (int s : {surface, volume}) {
            core::Species& sp = model.species[std::size_t(s)];
            sp.bondStiffness = bond;
            sp.bondBulk = c.bulk[std::size_t(k)];
            sp.alphaForceGm = m.shapeHold * bond;
            sp.alphaTorqueGm = m.shapeHold * bond * bop::kR0 * bop::kR0;
            // Mass 1: beta_v = m / t_relax; the rotation relaxes in the same time.
            params.drag[std::size_t(s)].v = 1.0 / c.units.fromS(m.relaxationS);
            params.drag[std::size_t(s)].w = model.integration.inertia * params.drag[std::size_t(s)].v;
        }
    }
}

std::vector<std::string> calibrationReport(const Calibration& c, const std::vector<Material>& materials,
                                           double timeStep) {
    const UnitSystem& u = c.units;
    std::vector<std::string> out;
    out.push_back("a bonded elastic volume: springs between the placed neighbours and a volume term (physics.md §8.3)");
    out.push_back(format("units: length %.4g mm, mass %.4g kg, time %.4g s, force %.4g N", u.lengthMm, u.massKg,
                         u.timeS, u.forceN()));
    out.push_back(
        format("time step %.4g s (%.4g simulation units); mass scaling %g", u.toS(timeStep), timeStep, c.massScaling));
    out.push_back(format("the stiffest material's P-wave modulus: %.4g kPa (%.4g energy / length^3)",
                         u.toKpa(kPWaveModulus), kPWaveModulus));
    for (std::size_t k = 0; k < materials.size(); ++k) {
        const Material& m = materials[k];
        out.push_back(
            "material '" + m.name +
            "': " + format("E %.4g kPa -> weight %.4g; Poisson %.3g", m.youngKpa, c.weight[k], m.poisson) +
            format("; density %.4g kg/m^3", m.densityKgM3) +
            format("; bonds k %.4g (energy / length^2), volume term B %.4g (energy / length^3)", c.bond[k], c.bulk[k]) +
            format("; relaxation %.4g s -> drag %.4g; map hold %.3g of a bond", m.relaxationS,
                   1.0 / u.fromS(m.relaxationS), m.shapeHold));
    }
    return out;
}

}  // namespace bop::app
