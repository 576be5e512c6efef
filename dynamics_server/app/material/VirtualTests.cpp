#include "app/material/VirtualTests.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/Units.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <unordered_map>

namespace bop::app {
namespace {

// Particles held between steps: each keeps its position (a plate's only its height) and no
// velocity, and the force on it is taken off before the next half kick. Held by id: the run
// reorders its particles (core/SpatialOrder.hpp).
struct Held {
    std::vector<std::uint64_t> id;
    std::vector<std::size_t> index;
    std::vector<Eigen::Vector3d> at;
    bool heightOnly = false;
    double load = 0;  // the force the rest exerted on them along z at the last hold, force units

    void add(const core::Particles& p, std::size_t i) {
        id.push_back(p.id[i]);
        index.push_back(i);
        at.push_back(p.pos[i]);
    }
    void locate(const core::Particles& p) {
        bool same = true;
        for (std::size_t k = 0; k < id.size() && same; ++k) same = index[k] < p.size() && p.id[index[k]] == id[k];
        if (same) return;
        std::unordered_map<std::uint64_t, std::size_t> where;
        for (std::size_t i = 0; i < p.size(); ++i) where[p.id[i]] = i;
        for (std::size_t k = 0; k < id.size(); ++k) {
            const auto it = where.find(id[k]);
            if (it == where.end())
                throw std::runtime_error("a held particle is gone (id " + std::to_string(id[k]) + ")");
            index[k] = it->second;
        }
    }
    void hold(core::Particles& p) {
        locate(p);
        load = 0;
        for (std::size_t i : index) load += p.force[i].z();
        for (std::size_t k = 0; k < index.size(); ++k) {
            const std::size_t i = index[k];
            if (heightOnly) {
                p.pos[i].z() = at[k].z();
                p.vel[i].z() = 0;
                p.force[i].z() = 0;
            } else {
                p.pos[i] = at[k];
                p.vel[i].setZero();
                p.force[i].setZero();
            }
        }
    }
};

// Steps the minimiser, holding `held` after each step, until `load()` settles (Relaxation).
long long relaxUnder(core::Run& run, const std::vector<Held*>& held, const std::function<double()>& load,
                     const Relaxation& r) {
    run.minimise(core::FireParams{});
    double last = std::numeric_limits<double>::quiet_NaN();
    long long steps = 0;
    while (steps < r.maxSteps) {
        for (long long s = 0; s < r.window; ++s) {
            run.step();
            for (Held* h : held) h->hold(run.simulation().particles());
        }
        steps += r.window;
        const double now = load();
        if (steps >= r.minSteps && std::abs(now - last) <= r.tolerance * std::max(std::abs(now), 1e-12)) break;
        last = now;
    }
    run.minimise(std::nullopt);
    return steps;
}

void requireOneProcess(const core::Run& run) {
    if (run.simulation().particles().size() != std::size_t(run.totals().particles))
        throw std::invalid_argument("virtual material tests run on one process");
}

}  // namespace

std::vector<IndentPoint> indent(core::Run& run, const Eigen::Vector2d& xy, const std::vector<double>& depths,
                                double baseDepth, const Relaxation& relax,
                                const std::function<void(const std::string&)>& progress) {
    requireOneProcess(run);
    const auto& sphere = run.simulation().model().probeSphere;
    if (!sphere) throw std::invalid_argument("indentation needs the probe as a sphere ([probe] radius_mm)");
    core::Particles& p = run.simulation().particles();
    double zLow = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& x : p.pos) zLow = std::min(zLow, x.z());
    Held base;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.pos[i].z() < zLow + baseDepth) base.add(p, i);
    // First contact: the sphere resting on the surface's mean plane beneath it, the mean height of
    // the top sheet's particles within R / 2 of the axis (the sheet is jittered about its voxels'
    // centres; its highest particle lies above the surface Hertz's depth is measured from).
    const double R = sphere->radius;
    const auto& model = run.simulation().model();
    double top = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < p.size(); ++i)
        if (model.isSurface(p.species[i]) && (p.pos[i].head<2>() - xy).norm() < 0.5 * R)
            top = std::max(top, p.pos[i].z());
    if (!std::isfinite(top)) throw std::invalid_argument("no surface particle lies beneath the sphere's axis");
    double sum = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (model.isSurface(p.species[i]) && (p.pos[i].head<2>() - xy).norm() < 0.5 * R && p.pos[i].z() > top - kR0) {
            sum += p.pos[i].z();
            ++n;
        }
    const double contact = sum / double(n) + R;
    std::vector<IndentPoint> out;
    for (double d : depths) {
        core::ProbeState probe;
        probe.active = true;
        probe.position = Eigen::Vector3d(xy.x(), xy.y(), contact - d);
        run.setProbe(probe);
        const auto load = [&] { return run.simulation().stats().forces.probeReaction.z(); };
        IndentPoint pt;
        pt.depth = d;
        pt.steps = relaxUnder(run, {&base}, load, relax);
        pt.force = load();
        out.push_back(pt);
        char line[160];
        std::snprintf(line, sizeof line, "depth %.4g: force %.5g after %lld steps", d, pt.force, pt.steps);
        if (progress) progress(line);
    }
    return out;
}

// The bag's cross-section in its map at height z: the voxels of any bag in that layer, length^2.
static double sectionArea(core::Run& run, double z) {
    const auto& map = run.simulation().mapInForce().map();
    if (!map) throw std::invalid_argument("compression needs the bag's gradient map");
    const double h = voxelLength(map->r0Voxels);
    const Dims& d = map->dims();
    const int layer = std::clamp(int(std::floor(z / h)) - map->origin.z(), 0, d.nz - 1);
    std::size_t inside = 0;
    for (int y = 0; y < d.ny; ++y)
        for (int x = 0; x < d.nx; ++x) inside += map->occ[d.index(x, y, layer)] != 0;
    return double(inside) * h * h;
}

std::vector<CompressPoint> compress(core::Run& run, const std::vector<double>& strains, double plateDepth,
                                    const Relaxation& relax, const std::function<void(const std::string&)>& progress) {
    requireOneProcess(run);
    core::Particles& p = run.simulation().particles();
    double zLow = std::numeric_limits<double>::infinity(), zHigh = -zLow;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const Eigen::Vector3d& x : p.pos) {
        zLow = std::min(zLow, x.z());
        zHigh = std::max(zHigh, x.z());
        centre += x.head<2>();
    }
    centre /= double(p.size());
    Held bottom, top;
    bottom.heightOnly = top.heightOnly = true;
    Held middle;  // the mid-height band's surface particles (not held: located by id)
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double z = p.pos[i].z();
        if (z < zLow + plateDepth) bottom.add(p, i);
        if (z > zHigh - plateDepth) top.add(p, i);
        if (std::abs(z - 0.5 * (zLow + zHigh)) < 0.15 * (zHigh - zLow) &&
            run.simulation().model().isSurface(p.species[i]))
            middle.add(p, i);
    }
    // The plates' layers move as one: the strain is over the distance between their mean heights.
    const auto meanZ = [](const Held& h) {
        double z = 0;
        for (const Eigen::Vector3d& x : h.at) z += x.z();
        return z / double(std::max<std::size_t>(1, h.at.size()));
    };
    const double height = meanZ(top) - meanZ(bottom);
    if (middle.id.empty()) throw std::invalid_argument("the bag's mid-height band holds no surface particle");
    const auto meanRadius = [&] {
        middle.locate(p);
        double r = 0;
        for (std::size_t i : middle.index) r += (p.pos[i].head<2>() - centre).norm();
        return r / double(middle.index.size());
    };
    const double radius0 = meanRadius();
    const double area = sectionArea(run, 0.5 * (zLow + zHigh));
    const std::vector<Eigen::Vector3d> topStart = top.at;
    std::vector<CompressPoint> out;
    for (double e : strains) {
        for (std::size_t k = 0; k < top.at.size(); ++k) top.at[k].z() = topStart[k].z() - e * height;
        top.hold(p);
        const auto load = [&] { return 0.5 * (top.load - bottom.load); };  // compression positive
        CompressPoint pt;
        pt.strain = e;
        pt.steps = relaxUnder(run, {&bottom, &top}, load, relax);
        pt.stress = load() / area;
        pt.lateralStrain = meanRadius() / radius0 - 1;
        out.push_back(pt);
        char line[200];
        std::snprintf(line, sizeof line, "strain %.4g: stress %.5g, lateral strain %.5g after %lld steps", e, pt.stress,
                      pt.lateralStrain, pt.steps);
        if (progress) progress(line);
    }
    return out;
}

}  // namespace bop::app
