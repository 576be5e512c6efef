// Loading NIfTI / raw scalar images and rasterizing them into object masks.
#include "TestUtil.hpp"
#include "bop/common/Error.hpp"
#include "shape/ImageRasterizer.hpp"
#include "shape/ScalarImage.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace fs = std::filesystem;
using bop::Dims;
using bop::Mask;
using bop::VoxelGrid;
using namespace bop::shape;

namespace {

// 20x16x12 image, spacing 0.8x0.8x1.2 mm: label 1 in [2,18)x[2,14)x[2,10), label 2 in
// [5,10)x[4,9)x[3,7) (inside the label-1 box), 0 elsewhere.
ScalarImage labelledImage() {
    ScalarImage img;
    img.dims = Dims{20, 16, 12};
    img.spacingMm = Eigen::Vector3d(0.8, 0.8, 1.2);
    img.originMm = Eigen::Vector3d::Zero();
    img.values.assign(img.dims.count(), 0.0f);
    for (int k = 0; k < 12; ++k)
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 20; ++i) {
                float v = 0;
                if (i >= 2 && i < 18 && j >= 2 && j < 14 && k >= 2 && k < 10) v = 1;
                if (i >= 5 && i < 10 && j >= 4 && j < 9 && k >= 3 && k < 7) v = 2;
                img.values[img.dims.index(i, j, k)] = v;
            }
    return img;
}

constexpr std::size_t kOuterBox = 16 * 12 * 8;  // voxels of label 1 or 2
constexpr std::size_t kInnerBox = 5 * 5 * 4;    // voxels of label 2

void requireSameImage(const ScalarImage& a, const ScalarImage& b) {
    REQUIRE(a.dims == b.dims);
    REQUIRE(a.spacingMm.isApprox(b.spacingMm, 1e-6));
    REQUIRE(a.values == b.values);
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Overwrites bytes at `offset` of an uncompressed file.
template <class T>
void patch(const std::string& path, std::streamoff offset, T value) {
    std::fstream f(path, std::ios::binary | std::ios::in | std::ios::out);
    f.seekp(offset);
    f.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

std::string errorText(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const bop::Error& e) {
        return e.what();
    }
    return "(no bop::Error thrown)";
}

}  // namespace

TEST_CASE("NIfTI 3D images round-trip through .nii and .nii.gz", "[shape][images]") {
    bop::test::TempDir dir("images");
    const ScalarImage img = labelledImage();
    for (const std::string name : {"labels.nii", "labels.nii.gz"}) {
        const std::string path = dir.file(name);
        writeNifti(path, img, "uint8");
        const auto loaded = loadNifti(path);
        REQUIRE(loaded.size() == 1);
        requireSameImage(loaded[0], img);
        REQUIRE(loaded[0].originMm == Eigen::Vector3d::Zero());
    }
    // Other dtypes keep the values.
    ScalarImage f = img;
    for (std::size_t i = 0; i < f.values.size(); ++i) f.values[i] = f.values[i] * 1.5f - 0.25f;
    writeNifti(dir.file("f.nii"), f, "float32");
    requireSameImage(loadNifti(dir.file("f.nii"))[0], f);
    writeNifti(dir.file("s.nii.gz"), img, "int16");
    requireSameImage(loadNifti(dir.file("s.nii.gz"))[0], img);
}

TEST_CASE("NIfTI 4D file loads one image per frame", "[shape][images]") {
    bop::test::TempDir dir("images");
    std::vector<ScalarImage> frames(3, labelledImage());
    for (int f = 0; f < 3; ++f)
        for (float& v : frames[std::size_t(f)].values) v *= float(f + 1) * 100.0f;  // up to 600: needs int16
    const std::string path = dir.file("frames.nii.gz");
    writeNifti4d(path, frames, "int16");
    const auto loaded = loadNifti(path);
    REQUIRE(loaded.size() == 3);
    for (int f = 0; f < 3; ++f) requireSameImage(loaded[std::size_t(f)], frames[std::size_t(f)]);

    // Frames of different dims are refused; out-of-range values are refused.
    frames[1].dims = Dims{2, 2, 2};
    REQUIRE_THROWS_AS(writeNifti4d(dir.file("bad.nii"), frames, "int16"), bop::Error);
    REQUIRE_THROWS_AS(writeNifti(dir.file("bad.nii"), frames[2], "uint8"), bop::Error);
}

TEST_CASE("NIfTI scl_slope/scl_inter are applied", "[shape][images]") {
    bop::test::TempDir dir("images");
    const ScalarImage img = labelledImage();
    const std::string path = dir.file("scaled.nii");
    writeNifti(path, img, "uint8");
    patch<float>(path, 112, 2.0f);   // scl_slope
    patch<float>(path, 116, 10.0f);  // scl_inter
    const auto loaded = loadNifti(path);
    REQUIRE(loaded.size() == 1);
    for (std::size_t i = 0; i < img.values.size(); ++i) REQUIRE(loaded[0].values[i] == 2.0f * img.values[i] + 10.0f);
}

TEST_CASE("NIfTI errors name the file", "[shape][images]") {
    bop::test::TempDir dir("images");
    const std::string missing = dir.file("missing.nii");
    const std::string msg = errorText([&] { loadNifti(missing); });
    REQUIRE_THAT(msg, Catch::Contains(missing));
    REQUIRE_THAT(msg, Catch::Contains("not found"));

    for (const std::string name : {"text.nii", "text.txt", "text.nii.gz"}) {
        const std::string path = dir.file(name);
        std::ofstream(path) << "this is not a NIfTI image, just some text that is long enough to fill a header "
                            << std::string(400, 'x') << "\n";
        const std::string m = errorText([&] { loadNifti(path); });
        REQUIRE_THAT(m, Catch::Contains(path));
        REQUIRE_THAT(m, Catch::Contains("not a NIfTI"));
    }

    // Unsupported datatype: a float64 file relabelled as int64 (same bitpix).
    const std::string i64 = dir.file("int64.nii");
    writeNifti(i64, labelledImage(), "float64");
    patch<std::int16_t>(i64, 70, 1024);  // datatype = NIFTI_TYPE_INT64
    const std::string m64 = errorText([&] { loadNifti(i64); });
    REQUIRE_THAT(m64, Catch::Contains(i64));
    REQUIRE_THAT(m64, Catch::Contains("INT64"));

    // Zero spacing.
    const std::string zs = dir.file("zero_spacing.nii");
    writeNifti(zs, labelledImage(), "uint8");
    patch<float>(zs, 80, 0.0f);  // pixdim[1]
    REQUIRE_THAT(errorText([&] { loadNifti(zs); }), Catch::Contains(zs));

    // Truncated data.
    const std::string tr = dir.file("truncated.nii");
    writeNifti(tr, labelledImage(), "uint8");
    fs::resize_file(tr, 352 + 100);
    REQUIRE_THAT(errorText([&] { loadNifti(tr); }), Catch::Contains(tr));
}

TEST_CASE("raw big-endian uint16 with a header loads equal", "[shape][images]") {
    bop::test::TempDir dir("images");
    const ScalarImage img = labelledImage();
    std::vector<unsigned char> bytes(64, 0xAB);  // 64-byte header
    for (int f = 0; f < 2; ++f)
        for (float v : img.values) {
            const auto u = static_cast<std::uint16_t>(v * 1000 + f * 7);  // > 255: byte order matters
            bytes.push_back(static_cast<unsigned char>(u >> 8));
            bytes.push_back(static_cast<unsigned char>(u & 0xFF));
        }
    const std::string path = dir.file("labels.raw");
    writeBytes(path, bytes);

    RawLayout layout;
    layout.dims = img.dims;
    layout.dtype = "uint16";
    layout.spacingMm = img.spacingMm;
    layout.bigEndian = true;
    layout.headerBytes = 64;
    layout.frames = 2;
    const auto loaded = loadRaw(path, layout);
    REQUIRE(loaded.size() == 2);
    for (int f = 0; f < 2; ++f) {
        ScalarImage expect = img;
        for (float& v : expect.values) v = v * 1000 + float(f * 7);
        requireSameImage(loaded[std::size_t(f)], expect);
    }

    // Wrong size: one frame too many.
    layout.frames = 3;
    const std::size_t need = 64 + 3 * img.dims.count() * 2;
    const std::string msg = errorText([&] { loadRaw(path, layout); });
    REQUIRE_THAT(msg, Catch::Contains(path));
    REQUIRE_THAT(msg, Catch::Contains(std::to_string(bytes.size()) + " bytes"));
    REQUIRE_THAT(msg, Catch::Contains(std::to_string(need) + " bytes"));

    layout.frames = 2;
    layout.dtype = "uint12";
    REQUIRE_THAT(errorText([&] { loadRaw(path, layout); }), Catch::Contains("float64"));
    layout.dtype = "uint16";
    REQUIRE_THAT(errorText([&] { loadRaw(dir.file("nope.raw"), layout); }), Catch::Contains("nope.raw"));
}

TEST_CASE("label and threshold selection rasterize onto aligned grids", "[shape][images]") {
    const ScalarImage aniso = labelledImage();
    const ImageSelect label2{ImageSelect::Mode::Label, 0.5, {2}};
    const ImageSelect label1{ImageSelect::Mode::Label, 0.5, {1}};
    const ImageSelect over05{ImageSelect::Mode::Threshold, 0.5, {1}};
    const ImageSelect over15{ImageSelect::Mode::Threshold, 1.5, {1}};
    REQUIRE(countSelected(aniso, label2) == kInnerBox);
    REQUIRE(countSelected(aniso, label1) == kOuterBox - kInnerBox);
    REQUIRE(countSelected(aniso, over05) == kOuterBox);
    REQUIRE(countSelected(aniso, over15) == kInnerBox);

    const auto box = imageBounds(aniso);
    REQUIRE(box.min().isApprox(Eigen::Vector3d::Zero()));
    REQUIRE(box.max().isApprox(Eigen::Vector3d(16.0, 12.8, 14.4)));

    const int pad = 3;
    SECTION("isotropic image, same spacing: exact copy with padding") {
        ScalarImage img = aniso;
        img.spacingMm = Eigen::Vector3d::Constant(0.8);
        img.originMm = Eigen::Vector3d(1.0, -2.0, 3.5);
        VoxelGrid grid;
        grid.voxelMm = 0.8;
        grid.originMm = img.originMm - Eigen::Vector3d::Constant(pad * 0.8);
        grid.dims = Dims{20 + 2 * pad, 16 + 2 * pad, 12 + 2 * pad};
        for (const ImageSelect& sel : {label2, label1, over05, over15}) {
            Mask out;
            rasterizeImage(img, sel, grid, out);
            REQUIRE(out.dims == grid.dims);
            std::size_t ones = 0;
            for (std::size_t idx = 0; idx < out.data.size(); ++idx) {
                const Eigen::Vector3i c = out.dims.coords(idx);
                const Eigen::Vector3i s = c - Eigen::Vector3i::Constant(pad);
                const bool expect = img.dims.contains(s.x(), s.y(), s.z()) &&
                                    isSelected(img.values[img.dims.index(s.x(), s.y(), s.z())], sel);
                REQUIRE(out.data[idx] == (expect ? 1 : 0));
                ones += out.data[idx];
            }
            REQUIRE(ones == countSelected(img, sel));
        }
    }
    SECTION("anisotropic image on a finer cubic grid: each image voxel becomes 2x2x3 grid voxels") {
        VoxelGrid grid;
        grid.voxelMm = 0.4;
        grid.originMm = Eigen::Vector3d::Constant(-pad * 0.4);
        grid.dims = Dims{40 + 2 * pad, 32 + 2 * pad, 36 + 2 * pad};
        for (const ImageSelect& sel : {label2, label1, over05, over15}) {
            Mask out;
            rasterizeImage(aniso, sel, grid, out);
            std::size_t ones = 0;
            for (std::size_t idx = 0; idx < out.data.size(); ++idx) {
                const Eigen::Vector3i c = out.dims.coords(idx) - Eigen::Vector3i::Constant(pad);
                const bool inside = c.minCoeff() >= 0 && c.x() < 40 && c.y() < 32 && c.z() < 36;
                const bool expect =
                    inside && isSelected(aniso.values[aniso.dims.index(c.x() / 2, c.y() / 2, c.z() / 3)], sel);
                REQUIRE(out.data[idx] == (expect ? 1 : 0));
                ones += out.data[idx];
            }
            REQUIRE(ones == 12 * countSelected(aniso, sel));
        }
        Mask out;
        rasterizeImage(aniso, label2, grid, out);
        // Label-2 box [5,10)x[4,9)x[3,7) maps to grid [13,23)x[11,21)x[12,24).
        REQUIRE(out(13, 11, 12) == 1);
        REQUIRE(out(22, 20, 23) == 1);
        REQUIRE(out(12, 11, 12) == 0);
        REQUIRE(out(22, 20, 24) == 0);
    }
    SECTION("grid entirely outside the image gives an empty mask") {
        VoxelGrid grid;
        grid.voxelMm = 1.0;
        grid.originMm = Eigen::Vector3d(100, 0, 0);
        grid.dims = Dims{5, 5, 5};
        Mask out;
        rasterizeImage(aniso, over05, grid, out);
        REQUIRE(out.data == std::vector<std::uint8_t>(125, 0));
    }
}
