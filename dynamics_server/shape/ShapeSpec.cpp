#include "ShapeSpec.hpp"

#include "Components.hpp"
#include "FileSources.hpp"

#include <filesystem>
#include <limits>
#include <sstream>

namespace bop::shape {
namespace fs = std::filesystem;
namespace {

std::string resolve(const ConfigTable& t, const std::string& key, const std::string& name) {
    fs::path p(name);
    if (p.is_relative()) p = fs::path(t.file()).parent_path() / p;
    if (!fs::exists(p)) t.fail(key, "file '" + p.string() + "' not found");
    return p.string();
}

double positive(const ConfigTable& t, const std::string& key, double v) {
    if (!(v > 0)) t.fail(key, "must be greater than 0, got " + std::to_string(v));
    return v;
}

ImageSelect readSelect(const ConfigTable& t) {
    ImageSelect s;
    if (t.has("label") && t.has("threshold")) t.fail("label", "give either 'label' or 'threshold', not both");
    if (t.has("label")) {
        s.mode = ImageSelect::Mode::Label;
        const toml::node* node = t.raw().get("label");
        s.labels = node && node->is_array() ? t.numbers("label") : std::vector<double>{t.number("label")};
        if (s.labels.empty()) t.fail("label", "expected a label value or a non-empty list of them");
    } else {
        s.threshold = t.number("threshold", 0.5);
    }
    return s;
}

// Checks that an image selection finds voxels in every frame.
void requireSelected(const ConfigTable& t, const std::vector<ScalarImage>& frames, const ImageSelect& s,
                     const std::string& file) {
    for (std::size_t f = 0; f < frames.size(); ++f) {
        if (countSelected(frames[f], s) > 0) continue;
        const auto [lo, hi] = std::minmax_element(frames[f].values.begin(), frames[f].values.end());
        std::ostringstream os;
        std::string labels;
        for (const double l : s.labels) labels += (labels.empty() ? "" : ", ") + std::to_string(l);
        os << "file '" << file << "' frame " << f << ": the "
           << (s.mode == ImageSelect::Mode::Label ? "label(s) " + labels : "threshold " + std::to_string(s.threshold))
           << " selects no voxels (values range from " << *lo << " to " << *hi << "); expected a non-empty object";
        t.fail(s.mode == ImageSelect::Mode::Label ? "label" : "threshold", os.str());
    }
}

// Frames cut to their own selection's boxes (one file each) put back on the box around them all,
// NaN (never selected) where a frame had no sample; frames of one spacing.
void onOneBox(std::vector<ScalarImage>& frames) {
    const Eigen::Vector3d h = frames.front().spacingMm;
    Eigen::Vector3i lo = Eigen::Vector3i::Constant(std::numeric_limits<int>::max()), hi = -lo;
    const auto corner = [&](const ScalarImage& img) {
        return Eigen::Vector3i((img.originMm.cwiseQuotient(h)).array().round().cast<int>());
    };
    for (const auto& img : frames) {
        lo = lo.cwiseMin(corner(img));
        hi = hi.cwiseMax(corner(img) + Eigen::Vector3i(img.dims.nx, img.dims.ny, img.dims.nz));
    }
    const Dims all{hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()};
    for (auto& img : frames) {
        if (img.dims == all && corner(img) == lo) continue;
        ScalarImage out{all, h, lo.cast<double>().cwiseProduct(h),
                        std::vector<float>(all.count(), std::numeric_limits<float>::quiet_NaN())};
        const Eigen::Vector3i shift = corner(img) - lo;
        for (int k = 0; k < img.dims.nz; ++k)
            for (int j = 0; j < img.dims.ny; ++j)
                for (int i = 0; i < img.dims.nx; ++i)
                    out.values[all.index(i + shift.x(), j + shift.y(), k + shift.z())] =
                        img.values[img.dims.index(i, j, k)];
        img = std::move(out);
    }
}

// Leaves only the largest face-connected piece of the selection in each frame (the others become
// NaN, which no selection takes); returns the dropped pieces' sizes for a warning, "" if none.
std::string keepLargestComponent(std::vector<ScalarImage>& frames, const ImageSelect& sel) {
    std::ostringstream os;
    for (std::size_t f = 0; f < frames.size(); ++f) {
        ScalarImage& img = frames[f];
        const Components c = findComponents(img.dims, [&](std::size_t v) { return isSelected(img.values[v], sel); });
        if (c.sizes.size() < 2) continue;
        for (std::size_t v = 0; v < img.values.size(); ++v)
            if (c.label[v] > 1) img.values[v] = std::numeric_limits<float>::quiet_NaN();
        os << (os.tellp() > 0 ? "; " : "") << (frames.size() > 1 ? "frame " + std::to_string(f) + ": " : "")
           << c.sizes.size() - 1 << " piece(s) of";
        for (std::size_t p = 1; p < c.sizes.size() && p <= 20; ++p) os << (p > 1 ? "," : "") << ' ' << c.sizes[p];
        os << (c.sizes.size() > 21 ? ", ..." : "") << " image voxels beside the kept " << c.sizes[0];
    }
    return os.str();
}

std::vector<std::string> imageFiles(const ConfigTable& t) {
    if (t.has("file") && t.has("files")) t.fail("files", "give either 'file' or 'files', not both");
    std::vector<std::string> names = t.has("files") ? t.strings("files") : std::vector<std::string>{t.string("file")};
    if (names.empty()) t.fail("files", "expected at least one file name");
    for (auto& n : names) n = resolve(t, t.has("files") ? "files" : "file", n);
    return names;
}

std::shared_ptr<ModelSource> readSource(const ConfigTable& t, double voxelMm, std::string& stamps) {
    const std::string kind = t.choice("source", {"superellipsoid", "sphere", "torus", "mesh", "nifti", "raw"}, "");
    const Eigen::Vector3d centre = t.vec3("center_mm", Eigen::Vector3d::Zero());
    auto stamp = [&](const std::string& f) {
        stamps += f + ":" + std::to_string(fs::file_size(f)) + ":" +
                  std::to_string(fs::last_write_time(f).time_since_epoch().count()) + "\n";
    };
    if (kind == "superellipsoid" || kind == "sphere") {
        SuperellipsoidParams p;
        p.centreMm = centre;
        if (kind == "sphere") {
            p.radiiMm.setConstant(positive(t, "radius_mm", t.number("radius_mm")));
        } else {
            p.radiiMm = t.vec3("radii_mm");
            for (int a = 0; a < 3; ++a) positive(t, "radii_mm", p.radiiMm[a]);
            const std::vector<double> e = t.numbers("exponents");
            if (e.size() != 2) t.fail("exponents", "expected 2 numbers [north_south, east_west]");
            p.e1 = positive(t, "exponents", e[0]);
            p.e2 = positive(t, "exponents", e[1]);
        }
        return makeSuperellipsoid(p);
    }
    if (kind == "torus") {
        TorusParams p;
        p.centreMm = centre;
        p.majorMm = positive(t, "major_radius_mm", t.number("major_radius_mm"));
        p.minorMm = positive(t, "minor_radius_mm", t.number("minor_radius_mm"));
        if (p.minorMm >= p.majorMm) t.fail("minor_radius_mm", "must be smaller than major_radius_mm");
        return makeTorus(p);
    }
    if (kind == "mesh") {
        const std::string file = resolve(t, "file", t.string("file"));
        stamp(file);
        MeshPlacement placement;
        placement.offsetMm = centre;
        if (t.has("fit_voxels")) {
            if (t.has("scale_mm")) t.fail("fit_voxels", "give either 'scale_mm' or 'fit_voxels', not both");
            placement.fitVoxels = int(t.integer("fit_voxels"));
            if (placement.fitVoxels < 1) t.fail("fit_voxels", "must be at least 1 voxel");
            if (!(voxelMm > 0)) t.fail("fit_voxels", "needs the voxel size: set [grid] voxel_size_mm");
            placement.voxelMm = voxelMm;
        } else {
            placement.scaleMm = positive(t, "scale_mm", t.number("scale_mm", 1.0));
        }
        return makeMeshSource(file, placement);
    }
    const std::vector<std::string> files = imageFiles(t);
    const ImageSelect sel = readSelect(t);
    const bool largest = t.choice("components", {"all", "largest"}, "all") == "largest";
    const KeepFn keep = [sel](float v) { return isSelected(v, sel); };  // each file cut to the selection's box
    std::vector<ScalarImage> frames;
    if (kind == "nifti") {
        for (const auto& f : files) {
            stamp(f);
            for (auto& img : loadNifti(f, keep)) frames.push_back(std::move(img));
        }
    } else {
        RawLayout layout;
        const std::vector<double> n = t.numbers("size_voxels");
        if (n.size() != 3) t.fail("size_voxels", "expected 3 integers [nx, ny, nz]");
        layout.dims = {int(n[0]), int(n[1]), int(n[2])};
        if (layout.dims.count() == 0) t.fail("size_voxels", "every size must be at least 1");
        layout.dtype =
            t.choice("dtype", {"uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64"}, "uint8");
        layout.spacingMm = t.vec3("spacing_mm", Eigen::Vector3d::Ones());
        for (int a = 0; a < 3; ++a) positive(t, "spacing_mm", layout.spacingMm[a]);
        layout.bigEndian = t.boolean("big_endian", false);
        layout.headerBytes = std::size_t(t.integer("header_bytes", 0));
        layout.frames = int(t.integer("frames", 1));
        for (const auto& f : files) {
            stamp(f);
            for (auto& img : loadRaw(f, layout, keep)) frames.push_back(std::move(img));
        }
    }
    for (std::size_t f = 1; f < frames.size(); ++f)
        if (frames[f].spacingMm != frames[0].spacingMm)
            t.fail(t.has("files") ? "files" : "file", "every frame of a sequence must share one voxel spacing");
    onOneBox(frames);
    for (auto& img : frames) img.originMm += centre;
    requireSelected(t, frames, sel, files.front());
    std::string what =
        kind + " " + files.front() + (files.size() > 1 ? " (+" + std::to_string(files.size() - 1) + " files)" : "");
    what += ", " + std::to_string(frames.size()) + " frame(s)";
    std::string dropped;  // components = "largest": the sizes left out
    if (largest) dropped = keepLargestComponent(frames, sel);
    auto source = makeImageSource(std::move(frames), sel, what);
    if (!dropped.empty()) source->setWarning("components = \"largest\" kept the largest piece; dropped " + dropped);
    return source;
}

}  // namespace

ShapeSpec readShapeSpec(const ConfigTable& root) {
    ShapeSpec s;
    s.sceneFile = root.file();
    const ConfigTable grid = root.table("grid");
    s.grid.voxelMm = grid.number("voxel_size_mm", 0.0);
    if (grid.has("voxel_size_mm")) positive(grid, "voxel_size_mm", s.grid.voxelMm);
    s.grid.paddingVoxels = int(grid.integer("padding_voxels", 4));
    if (s.grid.paddingVoxels < 1) grid.fail("padding_voxels", "must be at least 1 (the border counts as outside)");
    s.grid.r0Voxels = positive(grid, "r0_voxels", grid.number("r0_voxels", 2.0));
    if (grid.has("size_voxels")) {
        const std::vector<double> n = grid.numbers("size_voxels");
        if (n.size() != 3 || n[0] < 3 || n[1] < 3 || n[2] < 3)
            grid.fail("size_voxels", "expected 3 integers [nx, ny, nz], each at least 3");
        s.grid.size = Dims{int(n[0]), int(n[1]), int(n[2])};
    }
    grid.finish();

    const ConfigTable shape = root.table("shape");
    s.geometry.sigmaVoxels = positive(shape, "smoothing_sigma_voxels", shape.number("smoothing_sigma_voxels", 2.0));
    s.geometry.cpWeightC = shape.number("cp_weight_c", 4.0);
    if (s.geometry.cpWeightC < 0) shape.fail("cp_weight_c", "must be 0 or more");
    s.geometry.cpWeightForm = shape.choice("cp_weight_form", {"linear", "quadratic"}, "linear") == "linear"
                                  ? CpWeightForm::Linear
                                  : CpWeightForm::Quadratic;
    const std::string interp = shape.choice("interpolation", {"mixed", "trilinear", "nearest"}, "mixed");
    s.interpolation = interp == "mixed"       ? core::Interpolation::Mixed
                      : interp == "trilinear" ? core::Interpolation::Trilinear
                                              : core::Interpolation::Nearest;
    std::string stamps;
    const std::vector<ConfigTable> bags = shape.tableArray("bag");
    if (bags.empty() || bags.size() > 127) shape.fail("bag", "expected 1 to 127 [[shape.bag]] tables, outer to inner");
    for (std::size_t b = 0; b < bags.size(); ++b) {
        BagSpec bag;
        bag.key = bags[b].prefix();
        bag.name = bags[b].string("name", "bag" + std::to_string(b + 1));
        bag.source = readSource(bags[b], s.grid.voxelMm, stamps);
        if (const std::string w = bag.source->warning(); !w.empty()) s.warnings.push_back(bag.key + ": " + w);
        bags[b].finish();
        s.bags.push_back(std::move(bag));
    }
    shape.finish();
    if (!s.grid.voxelMm) {
        s.grid.voxelMm = s.bags.front().source->naturalVoxelMm();
        if (!s.grid.voxelMm) grid.fail("voxel_size_mm", "missing (required unless the outer bag is an image)");
    }
    std::ostringstream os;
    os << "grid " << s.grid.voxelMm << " " << s.grid.paddingVoxels << " " << s.grid.r0Voxels << "\n"
       << grid.raw() << "\n"
       << shape.raw() << "\n"
       << stamps;
    s.canonical = os.str();
    return s;
}

ShapeSpec loadShapeSpec(const std::string& sceneFile, const std::vector<std::string>& otherTables) {
    const toml::table doc = ConfigTable::parseFile(sceneFile);
    const ConfigTable root(doc, sceneFile, "");
    ShapeSpec s = readShapeSpec(root);
    for (const auto& t : otherTables) (void)root.has(t);
    root.finish();
    return s;
}

}  // namespace bop::shape
