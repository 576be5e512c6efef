#include "ShapeSpec.hpp"

#include "FileSources.hpp"
#include "ImageBags.hpp"

#include <filesystem>
#include <limits>
#include <sstream>

namespace bop::shape {
namespace fs = std::filesystem;
namespace {

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

std::shared_ptr<ModelSource> readSource(const ConfigTable& t, double voxelMm, std::string& stamps) {
    const std::string kind = t.choice("source", {"superellipsoid", "sphere", "torus", "mesh", "nifti", "raw"}, "");
    const Eigen::Vector3d centre = t.vec3("center_mm", Eigen::Vector3d::Zero());
    if (kind == "superellipsoid" || kind == "sphere") {
        SuperellipsoidParams p;
        p.centreMm = centre;
        if (kind == "sphere") {
            p.radiiMm.setConstant(positiveNumber(t, "radius_mm", t.number("radius_mm")));
        } else {
            p.radiiMm = t.vec3("radii_mm");
            for (int a = 0; a < 3; ++a) positiveNumber(t, "radii_mm", p.radiiMm[a]);
            const std::vector<double> e = t.numbers("exponents");
            if (e.size() != 2) t.fail("exponents", "expected 2 numbers [north_south, east_west]");
            p.e1 = positiveNumber(t, "exponents", e[0]);
            p.e2 = positiveNumber(t, "exponents", e[1]);
        }
        return makeSuperellipsoid(p);
    }
    if (kind == "torus") {
        TorusParams p;
        p.centreMm = centre;
        p.majorMm = positiveNumber(t, "major_radius_mm", t.number("major_radius_mm"));
        p.minorMm = positiveNumber(t, "minor_radius_mm", t.number("minor_radius_mm"));
        if (p.minorMm >= p.majorMm) t.fail("minor_radius_mm", "must be smaller than major_radius_mm");
        return makeTorus(p);
    }
    if (kind == "mesh") {
        const std::string file = resolveFile(t, "file", t.string("file"));
        stampFile(file, stamps);
        MeshPlacement placement;
        placement.offsetMm = centre;
        if (t.has("fit_voxels")) {
            if (t.has("scale_mm")) t.fail("fit_voxels", "give either 'scale_mm' or 'fit_voxels', not both");
            placement.fitVoxels = int(t.integer("fit_voxels"));
            if (placement.fitVoxels < 1) t.fail("fit_voxels", "must be at least 1 voxel");
            if (!(voxelMm > 0)) t.fail("fit_voxels", "needs the voxel size: set [grid] voxel_size_mm");
            placement.voxelMm = voxelMm;
        } else {
            placement.scaleMm = positiveNumber(t, "scale_mm", t.number("scale_mm", 1.0));
        }
        return makeMeshSource(file, placement);
    }
    const ImageSelect sel = readSelect(t);
    const bool largest = t.choice("components", {"all", "largest"}, "all") == "largest";
    ImageFrames img = readImageFrames(
        t, kind, [sel](float v) { return isSelected(v, sel); }, stamps);
    return imageBag(t, std::move(img), sel, largest);
}

}  // namespace

double readBoundarySmoothing(const ConfigTable& t, const std::string& kind) {
    const bool image = kind == "nifti" || kind == "raw";
    if (image && !t.has("boundary_smoothing_voxels")) return kImageDefaultSmoothing;
    const double w = t.number("boundary_smoothing_voxels", 0.0);
    if (!(w >= 0)) t.fail("boundary_smoothing_voxels", "must be 0 (off) or more, got " + std::to_string(w));
    return w;
}

ShapeSpec readShapeSpec(const ConfigTable& root) {
    ShapeSpec s;
    s.sceneFile = root.file();
    const ConfigTable grid = root.table("grid");
    s.grid.voxelMm = grid.number("voxel_size_mm", 0.0);
    if (grid.has("voxel_size_mm")) positiveNumber(grid, "voxel_size_mm", s.grid.voxelMm);
    s.grid.paddingVoxels = int(grid.integer("padding_voxels", 4));
    if (s.grid.paddingVoxels < 1) grid.fail("padding_voxels", "must be at least 1 (the border counts as outside)");
    s.grid.r0Voxels = positiveNumber(grid, "r0_voxels", grid.number("r0_voxels", 2.0));
    if (grid.has("size_voxels")) {
        const std::vector<double> n = grid.numbers("size_voxels");
        if (n.size() != 3 || n[0] < 3 || n[1] < 3 || n[2] < 3)
            grid.fail("size_voxels", "expected 3 integers [nx, ny, nz], each at least 3");
        s.grid.size = Dims{int(n[0]), int(n[1]), int(n[2])};
    }
    grid.finish();

    const ConfigTable shape = root.table("shape");
    s.geometry.sigmaVoxels =
        positiveNumber(shape, "smoothing_sigma_voxels", shape.number("smoothing_sigma_voxels", 2.0));
    s.geometry.cpWeightC = shape.number("cp_weight_c", 4.0);
    if (s.geometry.cpWeightC < 0) shape.fail("cp_weight_c", "must be 0 or more");
    s.geometry.cpWeightForm = shape.choice("cp_weight_form", {"linear", "quadratic"}, "linear") == "linear"
                                  ? CpWeightForm::Linear
                                  : CpWeightForm::Quadratic;
    const std::string interp = shape.choice("interpolation", {"mixed", "trilinear", "nearest"}, "mixed");
    s.interpolation = interp == "mixed"       ? Interpolation::Mixed
                      : interp == "trilinear" ? Interpolation::Trilinear
                                              : Interpolation::Nearest;
    std::string stamps;
    const std::vector<ConfigTable> bags = shape.tableArray("bag");
    if (bags.empty() || bags.size() > std::size_t(kMaxBags))
        shape.fail("bag", "expected 1 to " + std::to_string(kMaxBags) + " [[shape.bag]] tables");
    for (std::size_t b = 0; b < bags.size(); ++b) {
        if (bags[b].has("labels")) {  // one bag per label of a segmentation
            for (BagSpec& bag : labelBags(bags[b], s.grid, stamps, s.warnings)) s.bags.push_back(std::move(bag));
            bags[b].finish();
            continue;
        }
        BagSpec bag;
        bag.key = bags[b].prefix();
        bag.name = bags[b].string("name", "bag" + std::to_string(b + 1));
        bag.source = readSource(bags[b], s.grid.voxelMm, stamps);
        bag.boundarySmoothingVoxels = readBoundarySmoothing(bags[b], bags[b].string("source"));
        if (const std::string w = bag.source->warning(); !w.empty()) s.warnings.push_back(bag.key + ": " + w);
        bags[b].finish();
        s.bags.push_back(std::move(bag));
    }
    shape.finish();
    if (s.bags.size() > std::size_t(kMaxBags))
        shape.fail("bag", std::to_string(s.bags.size()) + " bags, at most " + std::to_string(kMaxBags) +
                              " fit the species numbers");
    if (!s.grid.voxelMm) {
        s.grid.voxelMm = s.bags.front().source->naturalVoxelMm();
        if (!s.grid.voxelMm) grid.fail("voxel_size_mm", "missing (required unless the outer bag is an image)");
    }
    for (BagSpec& bag : s.bags)  // an image's default: one of its coarsest samples
        if (bag.boundarySmoothingVoxels == kImageDefaultSmoothing)
            bag.boundarySmoothingVoxels = std::max(1.0, bag.source->coarsestSpacingMm() / s.grid.voxelMm);
    std::ostringstream os;
    os << "grid " << s.grid.voxelMm << " " << s.grid.paddingVoxels << " " << s.grid.r0Voxels << "\n"
       << grid.raw() << "\n"
       << shape.raw() << "\n"
       << "boundary smoothing v2:";
    for (const BagSpec& bag : s.bags) os << ' ' << bag.boundarySmoothingVoxels;
    os << "\n" << stamps;
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
