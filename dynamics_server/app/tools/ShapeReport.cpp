#include "app/tools/ShapeReport.hpp"

#include "bop/common/Error.hpp"
#include "bop/common/Npy.hpp"
#include "core/MapField.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>

namespace bop::app {
namespace fs = std::filesystem;

const std::set<std::string> kNpyArrays = {"labels", "species", "vectors", "distance", "normals", "curvature", "weight"};

namespace {

std::string frameDir(const std::string& dir, std::size_t f, std::size_t frames) {
    if (frames == 1) return dir;
    std::ostringstream os;
    os << dir << "/frame" << std::setw(2) << std::setfill('0') << f;
    return os.str();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
}

}  // namespace

void printShapeReport(std::ostream& os, const shape::ShapeSpec& spec, const shape::ShapeBuild& build) {
    const GradientMap& m0 = build.frames.front();
    const Dims& d = m0.dims();
    const double h = voxelLength(m0.r0Voxels);
    os << std::fixed << std::setprecision(3);
    os << "scene        " << spec.sceneFile << "\n";
    for (std::size_t b = 0; b < spec.bags.size(); ++b)
        os << "bag " << b + 1 << "        " << spec.bags[b].name << ": " << spec.bags[b].source->describe()
           << " (surface species " << surfaceSpeciesOfBag(int(b) + 1) << ", volume species "
           << volumeSpeciesOfBag(int(b) + 1) << ")\n";
    os << "grid         " << d.nx << " x " << d.ny << " x " << d.nz << " = " << d.count() << " voxels\n"
       << "voxel        " << m0.grid.voxelMm << " mm = " << h << " simulation units (r0 = " << m0.r0Voxels
       << " voxels = sqrt(3))\n"
       << "origin       " << m0.grid.originMm.transpose() << " mm\n";
    for (std::size_t f = 0; f < build.frames.size(); ++f) {
        const GradientMap& m = build.frames[f];
        std::map<int, std::size_t> perSpecies;
        for (auto o : m.occ) ++perSpecies[o];
        std::size_t surface = 0, inside = 0;
        for (const auto& [s, n] : perSpecies)
            if (s != 0) (isSurfaceSpecies(s) ? surface : inside) += n;
        os << "frame " << f << "      outside " << perSpecies[0] << ", surface " << surface << ", inside " << inside
           << " voxels; object volume " << (surface + inside) * std::pow(m.grid.voxelMm, 3) / 1000.0 << " mL\n";
        for (const auto& [s, n] : perSpecies)
            if (s)
                os << "  species " << s << " (" << (isSurfaceSpecies(s) ? "surface" : "volume") << ")  " << n
                   << " voxels\n";
        double outMax = 0, inMax = 0, sumAbs = 0;
        std::size_t nObj = 0;
        for (std::size_t v = 0; v < d.count(); ++v) {
            const double sd = m.signedDistance(v);
            outMax = std::max(outMax, sd);
            inMax = std::max(inMax, -sd);
            if (m.occ[v]) {
                sumAbs += std::abs(sd);
                ++nObj;
            }
        }
        os << "  distance   farthest outside " << outMax << " voxels (" << outMax * m.grid.voxelMm
           << " mm), deepest inside " << inMax << " voxels (" << inMax * m.grid.voxelMm << " mm), mean depth "
           << (nObj ? sumAbs / double(nObj) : 0.0) << " voxels\n";
        std::vector<double> kappa, weight, meanH;
        for (const auto& sv : m.surface) {
            kappa.push_back(sv.kappa / m.grid.voxelMm);
            weight.push_back(sv.cpWeight);
            meanH.push_back(sv.meanCurvature / m.grid.voxelMm);
        }
        const auto [wlo, whi] = std::minmax_element(weight.begin(), weight.end());
        os << "  curvature  median H " << median(meanH) << " 1/mm, median kappa (rms) " << median(kappa)
           << " 1/mm; co-planar weight " << *wlo << " to " << *whi << " (median " << median(weight) << ")\n";
    }
}

void printTimings(std::ostream& os, const std::vector<shape::StageTiming>& timings) {
    os << std::fixed;
    for (const auto& t : timings)
        os << "time         " << std::left << std::setw(10) << t.stage << std::right << std::setprecision(3)
           << t.seconds << " s  " << std::setprecision(1) << (t.items ? t.seconds * 1e9 / double(t.items) : 0.0)
           << " ns per " << (t.stage == "geometry" ? "surface voxel" : "voxel") << "\n";
}

void writeTimingsCsv(const std::string& path, const GradientMap& map, const std::vector<shape::StageTiming>& timings) {
    std::ofstream out(path);
    if (!out) throw Error(path, "cannot write the timings file");
    const Dims& d = map.dims();
    out << "stage,nx,ny,nz,seconds,items,ns_per_item\n";
    for (const auto& t : timings)
        out << t.stage << "," << d.nx << "," << d.ny << "," << d.nz << "," << t.seconds << "," << t.items << ","
            << (t.items ? t.seconds * 1e9 / double(t.items) : 0.0) << "\n";
}

void exportNpy(const std::string& dir, const shape::ShapeBuild& build, const std::set<std::string>& what) {
    for (std::size_t f = 0; f < build.frames.size(); ++f) {
        const GradientMap& m = build.frames[f];
        const std::string out = frameDir(dir, f, build.frames.size());
        fs::create_directories(out);
        const Dims& d = m.dims();
        const std::vector<std::size_t> shape{std::size_t(d.nz), std::size_t(d.ny), std::size_t(d.nx)};
        const std::vector<std::size_t> shape3{std::size_t(d.nz), std::size_t(d.ny), std::size_t(d.nx), 3};
        const std::size_t n = d.count();
        if (what.count("labels")) writeNpy(out + "/labels.npy", m.occ.data(), shape);
        if (what.count("species")) {
            std::vector<std::uint8_t> ns(n);
            for (std::size_t v = 0; v < n; ++v) ns[v] = std::uint8_t(m.nearestSpecies(v));
            writeNpy(out + "/species.npy", ns.data(), shape);
        }
        if (what.count("vectors")) {
            std::vector<std::int16_t> vec(3 * n);
            for (std::size_t v = 0; v < n; ++v) {
                const Eigen::Vector3i dv = m.delta(v);
                for (int a = 0; a < 3; ++a) vec[3 * v + a] = std::int16_t(dv[a]);
            }
            writeNpy(out + "/vectors.npy", vec.data(), shape3);
        }
        auto perVoxel = [&](const std::string& name, auto value) {
            std::vector<float> a(n);
            for (std::size_t v = 0; v < n; ++v) a[v] = value(v);
            writeNpy(out + "/" + name + ".npy", a.data(), shape);
        };
        if (what.count("distance")) perVoxel("distance", [&](std::size_t v) { return float(m.signedDistance(v)); });
        if (what.count("curvature")) perVoxel("curvature", [&](std::size_t v) { return m.nearestSurface(v).kappa; });
        if (what.count("weight")) perVoxel("cp_weight", [&](std::size_t v) { return m.nearestSurface(v).cpWeight; });
        if (what.count("normals")) {
            std::vector<float> a(3 * n);
            for (std::size_t v = 0; v < n; ++v)
                for (int c = 0; c < 3; ++c) a[3 * v + c] = m.nearestSurface(v).normal[c];
            writeNpy(out + "/normals.npy", a.data(), shape3);
        }
    }
}

}  // namespace bop::app
