#pragma once
// Image bags of a scene (nifti and raw sources): one bag from an image's selection (`label`,
// `threshold`), or one bag per label of a segmentation (`labels`), read from a [[shape.bag]] table.
#include "ImageRasterizer.hpp"
#include "ScalarImage.hpp"
#include "ShapeSpec.hpp"

#include <memory>
#include <string>
#include <vector>

namespace bop::shape {

// A file name of key `key`, relative to the scene's folder; fails naming the key when missing.
std::string resolveFile(const ConfigTable& t, const std::string& key, const std::string& name);
double positiveNumber(const ConfigTable& t, const std::string& key, double v);
// Adds a file's name, size and time to the cache key's text.
void stampFile(const std::string& path, std::string& stamps);

struct ImageFrames {
    std::vector<ScalarImage> frames;  // on one box and one spacing, offset by center_mm
    std::string what;                 // "nifti FILE, N frame(s)"
    std::string firstFile;
};
// The frames of the table's `file` or `files` (`kind` "nifti" or "raw"), each cut to the box of
// the values `keep` accepts.
ImageFrames readImageFrames(const ConfigTable& t, const std::string& kind, const KeepFn& keep, std::string& stamps);

// The source of one selection: it must select voxels in every frame; `largest` keeps its largest
// piece and names the others' sizes as a warning.
std::shared_ptr<ModelSource> imageBag(const ConfigTable& t, ImageFrames img, const ImageSelect& sel, bool largest);

// `labels = [a, b, ...]` or `labels = "all"`: one bag per label, named and coloured from
// `label_table` when given, else "<name>-<label>"; a label too small to hold a bag (fewer voxels
// than a ball of radius r0) is skipped with a warning naming it and its voxel count, and so is
// each piece of a label (face-connected) smaller than that: a speck beside an organ, a small node.
std::vector<BagSpec> labelBags(const ConfigTable& t, const GridSpec& grid, std::string& stamps,
                               std::vector<std::string>& warnings);

}  // namespace bop::shape
