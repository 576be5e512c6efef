#include "ImageBags.hpp"

#include "Components.hpp"
#include "FileSources.hpp"
#include "LabelTable.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

namespace bop::shape {
namespace fs = std::filesystem;
namespace {

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
// The box of `dims` voxels of img whose corner is img's voxel `lo` (which may lie outside img):
// NaN (never selected) where img has no sample.
ScalarImage boxOf(const ScalarImage& img, const Eigen::Vector3i& lo, const Dims& dims) {
    ScalarImage out{dims, img.spacingMm, img.originMm + lo.cast<double>().cwiseProduct(img.spacingMm),
                    std::vector<float>(dims.count(), std::numeric_limits<float>::quiet_NaN())};
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) {
                const Eigen::Vector3i c = lo + Eigen::Vector3i(i, j, k);
                if (img.dims.contains(c.x(), c.y(), c.z()))
                    out.values[dims.index(i, j, k)] = img.values[img.dims.index(c.x(), c.y(), c.z())];
            }
    return out;
}

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
        img = boxOf(img, lo - corner(img), all);
        img.originMm = lo.cast<double>().cwiseProduct(h);  // the box's corner as every frame has it
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

// Leaves out the face-connected pieces of the selection with fewer than `least` image voxels
// (they become NaN, which no selection takes); returns their sizes for a warning, "" if none.
std::string dropSpecks(std::vector<ScalarImage>& frames, const ImageSelect& sel, double least) {
    std::vector<std::size_t> dropped;
    for (ScalarImage& img : frames) {
        const Components c = findComponents(img.dims, [&](std::size_t v) { return isSelected(img.values[v], sel); });
        for (std::size_t v = 0; v < img.values.size(); ++v)
            if (c.label[v] > 0 && double(c.sizes[c.label[v] - 1]) < least)
                img.values[v] = std::numeric_limits<float>::quiet_NaN();
        for (const std::size_t n : c.sizes)
            if (double(n) < least) dropped.push_back(n);
    }
    if (dropped.empty()) return "";
    std::ostringstream os;
    os << dropped.size() << " piece(s) of";
    for (std::size_t p = 0; p < dropped.size() && p < 20; ++p) os << (p ? ", " : " ") << dropped[p];
    os << (dropped.size() > 20 ? ", ..." : "") << " image voxels";
    return os.str();
}

std::vector<std::string> imageFiles(const ConfigTable& t) {
    if (t.has("file") && t.has("files")) t.fail("files", "give either 'file' or 'files', not both");
    std::vector<std::string> names = t.has("files") ? t.strings("files") : std::vector<std::string>{t.string("file")};
    if (names.empty()) t.fail("files", "expected at least one file name");
    for (auto& n : names) n = resolveFile(t, t.has("files") ? "files" : "file", n);
    return names;
}

// The frames cut to the box of the voxels `sel` selects in any frame.
ImageFrames cutToSelection(const ImageFrames& img, const ImageSelect& sel) {
    const Dims& d = img.frames.front().dims;
    Eigen::Vector3i lo = Eigen::Vector3i::Constant(std::numeric_limits<int>::max()), hi = -lo;
    for (const auto& f : img.frames)
        for (std::size_t v = 0; v < f.values.size(); ++v)
            if (isSelected(f.values[v], sel)) {
                lo = lo.cwiseMin(d.coords(v));
                hi = hi.cwiseMax(d.coords(v) + Eigen::Vector3i::Ones());
            }
    ImageFrames out{{}, img.what, img.firstFile};
    const Dims cut{hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()};
    for (const auto& f : img.frames) out.frames.push_back(boxOf(f, lo, cut));
    return out;
}

// A species name from a label table's: no spaces (snapshots write names as words).
std::string asName(const std::string& text) {
    std::string out;
    for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
    return out.empty() ? "label" : out;
}

std::string labelText(double label) {
    std::ostringstream os;
    os << label;
    return os.str();
}

}  // namespace

std::string resolveFile(const ConfigTable& t, const std::string& key, const std::string& name) {
    fs::path p(name);
    if (p.is_relative()) p = fs::path(t.file()).parent_path() / p;
    if (!fs::exists(p)) t.fail(key, "file '" + p.string() + "' not found");
    return p.string();
}

double positiveNumber(const ConfigTable& t, const std::string& key, double v) {
    if (!(v > 0)) t.fail(key, "must be greater than 0, got " + std::to_string(v));
    return v;
}

void stampFile(const std::string& f, std::string& stamps) {
    stamps += f + ":" + std::to_string(fs::file_size(f)) + ":" +
              std::to_string(fs::last_write_time(f).time_since_epoch().count()) + "\n";
}

ImageFrames readImageFrames(const ConfigTable& t, const std::string& kind, const KeepFn& keep, std::string& stamps) {
    const std::vector<std::string> files = imageFiles(t);
    std::vector<ScalarImage> frames;
    if (kind == "nifti") {
        for (const auto& f : files) {
            stampFile(f, stamps);
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
        for (int a = 0; a < 3; ++a) positiveNumber(t, "spacing_mm", layout.spacingMm[a]);
        layout.bigEndian = t.boolean("big_endian", false);
        layout.headerBytes = std::size_t(t.integer("header_bytes", 0));
        layout.frames = int(t.integer("frames", 1));
        for (const auto& f : files) {
            stampFile(f, stamps);
            for (auto& img : loadRaw(f, layout, keep)) frames.push_back(std::move(img));
        }
    }
    for (std::size_t f = 1; f < frames.size(); ++f)
        if (frames[f].spacingMm != frames[0].spacingMm)
            t.fail(t.has("files") ? "files" : "file", "every frame of a sequence must share one voxel spacing");
    onOneBox(frames);
    const Eigen::Vector3d centre = t.vec3("center_mm", Eigen::Vector3d::Zero());
    for (auto& img : frames) img.originMm += centre;
    std::string what =
        kind + " " + files.front() + (files.size() > 1 ? " (+" + std::to_string(files.size() - 1) + " files)" : "");
    what += ", " + std::to_string(frames.size()) + " frame(s)";
    return {std::move(frames), what, files.front()};
}

std::shared_ptr<ModelSource> imageBag(const ConfigTable& t, ImageFrames img, const ImageSelect& sel, bool largest) {
    requireSelected(t, img.frames, sel, img.firstFile);
    std::string dropped;  // components = "largest": the sizes left out
    if (largest) dropped = keepLargestComponent(img.frames, sel);
    std::shared_ptr<ModelSource> source = makeImageSource(std::move(img.frames), sel, img.what);
    if (!dropped.empty()) source->setWarning("components = \"largest\" kept the largest piece; dropped " + dropped);
    return source;
}

std::vector<BagSpec> labelBags(const ConfigTable& t, const GridSpec& grid, std::string& stamps,
                               std::vector<std::string>& warnings) {
    const std::string kind = t.choice("source", {"nifti", "raw"}, "");
    if (t.has("label") || t.has("threshold")) t.fail("labels", "give 'labels' alone, not with 'label' or 'threshold'");
    const toml::node* node = t.raw().get("labels");
    const bool all = node && node->is_string();
    if (all && t.string("labels") != "all") t.fail("labels", "expected a list of label values or \"all\"");
    std::vector<double> wanted = all ? std::vector<double>{} : t.numbers("labels");
    if (!all && wanted.empty()) t.fail("labels", "expected a non-empty list of label values or \"all\"");
    const bool largest = t.choice("components", {"all", "largest"}, "all") == "largest";
    const KeepFn keep =
        all ? KeepFn([](float v) { return v != 0 && !std::isnan(v); })
            : KeepFn([wanted](float v) { return std::find(wanted.begin(), wanted.end(), double(v)) != wanted.end(); });
    const ImageFrames img = readImageFrames(t, kind, keep, stamps);
    std::map<double, std::size_t> voxels;  // per label, over every frame
    for (const auto& f : img.frames)
        for (float v : f.values)
            if (keep(v)) ++voxels[double(v)];
    std::string present;
    for (const auto& [label, n] : voxels) present += (present.empty() ? "" : ", ") + labelText(label);
    for (const double l : wanted)
        if (!voxels.count(l))
            t.fail("labels", "label " + labelText(l) + " is not in file '" + img.firstFile +
                                 "' (of the labels listed it holds " +
                                 (present.empty() ? std::string("none") : "only " + present) + ")");
    if (all) {
        if (voxels.empty()) t.fail("labels", "file '" + img.firstFile + "' holds no label other than 0");
        for (const auto& [label, n] : voxels)
            if (label != std::round(label))
                t.fail("labels", "\"all\" needs an image of whole-number labels; file '" + img.firstFile + "' holds " +
                                     labelText(label));
        for (const auto& [label, n] : voxels) wanted.push_back(label);
    }
    std::map<int, LabelEntry> table;
    if (t.has("label_table")) {
        const std::string path = resolveFile(t, "label_table", t.string("label_table"));
        stampFile(path, stamps);
        table = readLabelTable(path);
    }
    const std::string base = t.string("name", "label");
    const double smoothing = readBoundarySmoothing(t, kind);
    // The least a bag holds: a ball of radius r0 (a sheet around one volume particle), in image voxels.
    const Eigen::Vector3d h = img.frames.front().spacingMm;
    const double voxelMm = grid.voxelMm > 0 ? grid.voxelMm : h.minCoeff();
    const double least = 4.0 / 3.0 * M_PI * std::pow(grid.r0Voxels * voxelMm, 3) / h.prod() * double(img.frames.size());
    std::vector<BagSpec> bags;
    for (const double label : wanted) {
        const auto entry = table.find(int(label));
        const std::string name = entry != table.end() ? asName(entry->second.name) : base + "-" + labelText(label);
        if (double(voxels[label]) < least) {
            warnings.push_back(t.prefix() + ": label " + labelText(label) + " ('" + name + "') has " +
                               std::to_string(voxels[label]) + " voxels, fewer than the " +
                               std::to_string(std::llround(std::ceil(least))) +
                               " of a ball of radius r0 that a bag needs: skipped");
            continue;
        }
        ImageSelect sel;
        sel.mode = ImageSelect::Mode::Label;
        sel.labels = {label};
        ImageFrames cut = cutToSelection(img, sel);
        const std::string specks = dropSpecks(cut.frames, sel, least / double(img.frames.size()));
        if (!specks.empty()) {
            const bool none = std::any_of(cut.frames.begin(), cut.frames.end(),
                                          [&](const ScalarImage& f) { return countSelected(f, sel) == 0; });
            warnings.push_back(t.prefix() + ": label " + labelText(label) + " ('" + name + "'): " + specks +
                               ", each fewer than the " + std::to_string(std::llround(std::ceil(least))) +
                               " of a ball of radius r0 that a bag needs: " +
                               (none ? "every piece is, so the label is skipped" : "skipped"));
            if (none) continue;
            cut = cutToSelection(cut, sel);
        }
        BagSpec bag;
        bag.key = t.prefix();
        bag.name = name;
        if (entry != table.end()) bag.colour = entry->second.colour;
        bag.boundarySmoothingVoxels = smoothing;
        bag.source = imageBag(t, std::move(cut), sel, largest);
        if (const std::string w = bag.source->warning(); !w.empty())
            warnings.push_back(bag.key + ": " + name + ": " + w);
        bags.push_back(std::move(bag));
    }
    if (bags.empty()) t.fail("labels", "every label is too small to hold a bag (see the warnings)");
    return bags;
}

}  // namespace bop::shape
