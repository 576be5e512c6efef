#include "ScalarImage.hpp"

#include "bop/common/Error.hpp"

#include <nifti1_io.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <span>
#include <sstream>
#include <type_traits>

namespace bop::shape {
namespace {

struct DtypeInfo {
    const char* name;   // dtype name as used in RawLayout and writeNifti
    int niftiCode;      // NIFTI_TYPE_* code
    std::size_t bytes;  // bytes per sample
};

constexpr DtypeInfo kDtypes[] = {
    {"uint8", NIFTI_TYPE_UINT8, 1},     {"int8", NIFTI_TYPE_INT8, 1},       {"uint16", NIFTI_TYPE_UINT16, 2},
    {"int16", NIFTI_TYPE_INT16, 2},     {"uint32", NIFTI_TYPE_UINT32, 4},   {"int32", NIFTI_TYPE_INT32, 4},
    {"float32", NIFTI_TYPE_FLOAT32, 4}, {"float64", NIFTI_TYPE_FLOAT64, 8},
};

const char* acceptedDtypes() {
    return "uint8, int8, uint16, int16, uint32, int32, float32, float64";
}

const DtypeInfo& dtypeByName(const std::string& where, const std::string& name) {
    for (const auto& d : kDtypes)
        if (name == d.name) return d;
    throw Error(where, "unknown dtype '" + name + "'; accepted: " + acceptedDtypes());
}

const DtypeInfo* dtypeByCode(int code) {
    for (const auto& d : kDtypes)
        if (code == d.niftiCode) return &d;
    return nullptr;
}

struct NimDeleter {
    void operator()(nifti_image* nim) const { nifti_image_free(nim); }
};
using NimPtr = std::unique_ptr<nifti_image, NimDeleter>;

// Calls fn(T{}) with T the C++ type of NIfTI datatype `code` (one of kDtypes).
template <class Fn>
void visitDtype(int code, Fn&& fn) {
    switch (code) {
        case NIFTI_TYPE_UINT8:
            fn(std::uint8_t{});
            return;
        case NIFTI_TYPE_INT8:
            fn(std::int8_t{});
            return;
        case NIFTI_TYPE_UINT16:
            fn(std::uint16_t{});
            return;
        case NIFTI_TYPE_INT16:
            fn(std::int16_t{});
            return;
        case NIFTI_TYPE_UINT32:
            fn(std::uint32_t{});
            return;
        case NIFTI_TYPE_INT32:
            fn(std::int32_t{});
            return;
        case NIFTI_TYPE_FLOAT32:
            fn(float{});
            return;
        default:
            fn(double{});
            return;
    }
}

// Splits `nFrames` consecutive volumes of `dims` samples (native byte order) into ScalarImages,
// value = slope * sample + inter. With `keep`, every frame is cut to the box of the voxels whose
// value it accepts in any frame (the origin moves to the box's corner), so that a small organ of a
// large scan costs its own size; an image where it accepts none is returned whole.
std::vector<ScalarImage> splitFrames(const DtypeInfo& d, const unsigned char* data, Dims dims,
                                     const Eigen::Vector3d& spacingMm, int nFrames, double slope, double inter,
                                     const KeepFn& keep) {
    const std::size_t n = dims.count();
    const auto valueAt = [&](std::size_t i) {  // i: sample index over all frames
        float out = 0;
        visitDtype(d.niftiCode, [&](auto tag) {
            using T = decltype(tag);
            T v;
            std::memcpy(&v, data + i * sizeof(T), sizeof(T));
            out = float(slope * double(v) + inter);
        });
        return out;
    };
    Eigen::Vector3i lo(0, 0, 0), hi(dims.nx, dims.ny, dims.nz);  // box kept, voxels [lo, hi)
    if (keep) {
        Eigen::Vector3i first(dims.nx, dims.ny, dims.nz), last(-1, -1, -1);
        for (int f = 0; f < nFrames; ++f)
            for (int k = 0; k < dims.nz; ++k)
                for (int j = 0; j < dims.ny; ++j)
                    for (int i = 0; i < dims.nx; ++i)
                        if (keep(valueAt(std::size_t(f) * n + dims.index(i, j, k)))) {
                            const Eigen::Vector3i at(i, j, k);
                            first = first.cwiseMin(at);
                            last = last.cwiseMax(at);
                        }
        if (last.x() >= 0) lo = first, hi = last + Eigen::Vector3i::Ones();
    }
    const Dims kept{hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()};
    std::vector<ScalarImage> out(static_cast<std::size_t>(nFrames));
    for (int f = 0; f < nFrames; ++f) {
        ScalarImage& img = out[std::size_t(f)];
        img.dims = kept;
        img.spacingMm = spacingMm;
        img.originMm = lo.cast<double>().cwiseProduct(spacingMm);
        img.values.resize(kept.count());
        std::size_t o = 0;
        for (int k = lo.z(); k < hi.z(); ++k)
            for (int j = lo.y(); j < hi.y(); ++j)
                for (int i = lo.x(); i < hi.x(); ++i)
                    img.values[o++] = valueAt(std::size_t(f) * n + dims.index(i, j, k));
    }
    return out;
}

void requireReadable(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path, "file not found");
    if (std::filesystem::is_directory(path, ec)) throw Error(path, "is a directory, expected a file");
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error(path, "file cannot be opened for reading");
}

std::string dimsText(Dims d) {
    return std::to_string(d.nx) + " x " + std::to_string(d.ny) + " x " + std::to_string(d.nz);
}

void checkSpacing(const std::string& where, const Eigen::Vector3d& s) {
    for (int a = 0; a < 3; ++a)
        if (!(s[a] > 0.0) || !std::isfinite(s[a])) {
            std::ostringstream os;
            os << "voxel spacing must be positive and finite, got " << s[0] << " x " << s[1] << " x " << s[2] << " mm";
            throw Error(where, os.str());
        }
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Converts `v` for storage as dtype `d` and writes it at `dst`.
void storeSample(const std::string& path, const DtypeInfo& d, double v, unsigned char* dst) {
    visitDtype(d.niftiCode, [&](auto tag) {
        using T = decltype(tag);
        double r = v;
        if constexpr (std::is_integral_v<T>) {
            r = std::nearbyint(v);
            if (!(r >= double(std::numeric_limits<T>::lowest()) && r <= double(std::numeric_limits<T>::max()))) {
                std::ostringstream os;
                os << "value " << v << " does not fit dtype " << d.name;
                throw Error(path, os.str());
            }
        }
        const T t = T(r);
        std::memcpy(dst, &t, sizeof(T));
    });
}

// Reads the voxel data of a header-only nifti_image in native byte order. Done here rather than by
// nifti_image_load, which zero-fills a truncated file with only a warning and replaces
// non-finite floats by 0.
std::vector<unsigned char> readNiftiData(const std::string& path, nifti_image* nim) {
    const std::size_t need = nim->nvox * std::size_t(nim->nbyper);
    std::vector<unsigned char> buf(need);
    if (nim->iname_offset < 0) {  // offset counted from the end of the file (ASCII or odd ANALYZE headers)
        if (nifti_image_load(nim) != 0 || !nim->data) throw Error(path, "image data could not be read");
        std::memcpy(buf.data(), nim->data, need);
        nifti_image_unload(nim);
        return buf;
    }
    znzFile fp = znzopen(nim->iname, "rb", nifti_is_gzfile(nim->iname));
    if (znz_isnull(fp)) throw Error(path, std::string("cannot open image data file ") + nim->iname);
    std::size_t got = 0;
    if (znzseek(fp, znz_off_t(nim->iname_offset), SEEK_SET) >= 0) got = znzread(buf.data(), 1, need, fp);
    znzclose(fp);
    if (got != need)
        throw Error(path, "image data is truncated: " + std::to_string(got) + " of " + std::to_string(need) +
                              " bytes after offset " + std::to_string(nim->iname_offset));
    if (nim->nbyper > 1 && nim->byteorder != nifti_short_order())
        for (std::size_t i = 0; i < need; i += std::size_t(nim->nbyper))
            std::reverse(buf.begin() + std::ptrdiff_t(i), buf.begin() + std::ptrdiff_t(i) + nim->nbyper);
    return buf;
}

// Writes `frames` as one NIfTI-1 image: 3D (dim[0] = 3, one frame) or 4D (dim[0] = 4).
void writeFrames(const std::string& path, std::span<const ScalarImage> frames, const std::string& dtype, bool as4d) {
    const DtypeInfo& d = dtypeByName(path, dtype);
    if (!endsWith(path, ".nii") && !endsWith(path, ".nii.gz"))
        throw Error(path, "output file name must end in .nii or .nii.gz");
    if (frames.empty()) throw Error(path, "no frames to write");
    const Dims dims = frames.front().dims;
    if (dims.nx <= 0 || dims.ny <= 0 || dims.nz <= 0)
        throw Error(path, "image dims must be positive, got " + dimsText(dims));
    for (std::size_t f = 0; f < frames.size(); ++f) {
        if (!(frames[f].dims == dims) || frames[f].spacingMm != frames.front().spacingMm)
            throw Error(path, "frame " + std::to_string(f) + " has dims " + dimsText(frames[f].dims) +
                                  " or spacing differing from frame 0 (" + dimsText(dims) + ")");
        if (frames[f].values.size() != dims.count())
            throw Error(path, "frame " + std::to_string(f) + " holds " + std::to_string(frames[f].values.size()) +
                                  " values, its dims need " + std::to_string(dims.count()));
    }
    const Eigen::Vector3d sp = frames.front().spacingMm;
    checkSpacing(path, sp);

    int dimArr[8] = {as4d ? 4 : 3, dims.nx, dims.ny, dims.nz, int(frames.size()), 1, 1, 1};
    NimPtr nim(nifti_make_new_nim(dimArr, d.niftiCode, 1));
    if (!nim || !nim->data) throw Error(path, "cannot allocate NIfTI image");
    nim->dx = nim->pixdim[1] = float(sp[0]);
    nim->dy = nim->pixdim[2] = float(sp[1]);
    nim->dz = nim->pixdim[3] = float(sp[2]);
    nim->dt = nim->pixdim[4] = 1.0f;
    nim->xyz_units = NIFTI_UNITS_MM;
    nim->time_units = NIFTI_UNITS_SEC;
    nim->scl_slope = nim->scl_inter = 0.0f;  // no scaling
    nim->qform_code = nim->sform_code = 0;   // orientation unspecified; readers use pixdim

    auto* data = static_cast<unsigned char*>(nim->data);
    const std::size_t n = dims.count();
    for (std::size_t f = 0; f < frames.size(); ++f)
        for (std::size_t i = 0; i < n; ++i)
            storeSample(path, d, double(frames[f].values[i]), data + (f * n + i) * d.bytes);

    if (nifti_set_filenames(nim.get(), path.c_str(), 0, 1) != 0)
        throw Error(path, "niftiio rejected the output file name");

    std::error_code ec;
    std::filesystem::remove(path, ec);  // a stale file must not pass the check below
    nifti_image_write(nim.get());
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    const std::uintmax_t expected = std::uintmax_t(nim->iname_offset) + std::uintmax_t(nim->nvox) * d.bytes;
    if (ec || size == 0 || (endsWith(path, ".nii") && size != expected))
        throw Error(path, "writing the NIfTI file failed (directory missing or not writable?)");
}

}  // namespace

std::vector<ScalarImage> loadNifti(const std::string& path, const KeepFn& keep) {
    requireReadable(path);
    if (is_nifti_file(path.c_str()) < 0)
        throw Error(path, "not a NIfTI-1 file (no valid 348-byte header; NIfTI-2 is not supported)");

    NimPtr nim(nifti_image_read(path.c_str(), 0));  // header only; the data is read below
    if (!nim || !nim->fname || !nim->iname)
        throw Error(path,
                    "NIfTI header could not be interpreted (invalid dimensions or datatype, "
                    "or the .img file of a .hdr/.img pair is missing)");

    const DtypeInfo* d = dtypeByCode(nim->datatype);
    if (!d)
        throw Error(path, std::string("unsupported datatype ") + nifti_datatype_string(nim->datatype) + " (code " +
                              std::to_string(nim->datatype) + "); accepted: " + acceptedDtypes());

    // niftiio replaces zero dims and non-positive pixdims by 1, so both come from the header as stored.
    int dim[8];
    float pixdim[8];
    for (int a = 0; a < 8; ++a) dim[a] = nim->dim[a], pixdim[a] = nim->pixdim[a];
    if (std::unique_ptr<nifti_1_header, decltype(&std::free)> hdr{nifti_read_header(nim->fname, nullptr, 0),
                                                                  &std::free}) {
        for (int a = 0; a < 8; ++a) dim[a] = hdr->dim[a], pixdim[a] = hdr->pixdim[a];
    }
    const int ndim = dim[0];
    if (ndim < 1 || ndim > 7) throw Error(path, "invalid dim[0] = " + std::to_string(ndim));
    int size[5] = {0, 1, 1, 1, 1};  // size[a] = extent of axis a (1..4), 1 beyond dim[0]
    for (int a = 1; a <= ndim; ++a) {
        if (dim[a] <= 0)
            throw Error(path, "dimension " + std::to_string(a) + " has size " + std::to_string(dim[a]) +
                                  "; all dimensions must be at least 1");
        if (a <= 4)
            size[a] = dim[a];
        else if (dim[a] != 1)
            throw Error(path, "image has " + std::to_string(ndim) + " dimensions (dim[" + std::to_string(a) +
                                  "] = " + std::to_string(dim[a]) + "); only 3D and 4D images are supported");
    }
    const Dims dims{size[1], size[2], size[3]};
    const int nFrames = size[4];

    double toMm = 1.0;
    const int units = XYZT_TO_SPACE(nim->xyz_units);
    if (units == NIFTI_UNITS_METER)
        toMm = 1000.0;
    else if (units == NIFTI_UNITS_MICRON)
        toMm = 0.001;
    Eigen::Vector3d spacing;
    for (int a = 0; a < 3; ++a) {
        double s = std::fabs(double(pixdim[a + 1]));
        if (a + 1 > ndim && !(s > 0.0)) s = 1.0;  // unused axis without a spacing: 1 mm
        spacing[a] = s * toMm;
    }
    checkSpacing(path, spacing);

    if (nim->nvox != dims.count() * std::size_t(nFrames) || std::size_t(nim->nbyper) != d->bytes)
        throw Error(path, "image data size does not match its dimensions and datatype");
    const std::vector<unsigned char> data = readNiftiData(path, nim.get());

    double slope = 1.0, inter = 0.0;
    if (std::isfinite(nim->scl_slope) && nim->scl_slope != 0.0f) {
        slope = nim->scl_slope;
        inter = std::isfinite(nim->scl_inter) ? double(nim->scl_inter) : 0.0;
    }
    return splitFrames(*d, data.data(), dims, spacing, nFrames, slope, inter, keep);
}

std::vector<ScalarImage> loadRaw(const std::string& path, const RawLayout& layout, const KeepFn& keep) {
    const DtypeInfo& d = dtypeByName(path, layout.dtype);
    if (layout.dims.nx <= 0 || layout.dims.ny <= 0 || layout.dims.nz <= 0)
        throw Error(path, "raw layout dims must be positive, got " + dimsText(layout.dims));
    if (layout.frames < 1)
        throw Error(path, "raw layout frames must be at least 1, got " + std::to_string(layout.frames));
    checkSpacing(path, layout.spacingMm);
    requireReadable(path);

    std::error_code ec;
    const std::uintmax_t have = std::filesystem::file_size(path, ec);
    if (ec) throw Error(path, "cannot determine file size: " + ec.message());
    const std::size_t dataBytes = std::size_t(layout.frames) * layout.dims.count() * d.bytes;
    const std::size_t need = layout.headerBytes + dataBytes;
    if (have != need) {
        std::ostringstream os;
        os << "file holds " << have << " bytes, the layout (" << dimsText(layout.dims) << ", " << d.name << ", "
           << layout.frames << (layout.frames == 1 ? " frame, " : " frames, ") << layout.headerBytes
           << " header bytes) needs " << need << " bytes";
        throw Error(path, os.str());
    }

    std::vector<unsigned char> buf(dataBytes);
    std::ifstream f(path, std::ios::binary);
    f.seekg(std::streamoff(layout.headerBytes));
    f.read(reinterpret_cast<char*>(buf.data()), std::streamsize(dataBytes));
    if (!f) throw Error(path, "read failed after " + std::to_string(f.gcount()) + " data bytes");

    const bool hostBig = std::endian::native == std::endian::big;
    if (d.bytes > 1 && layout.bigEndian != hostBig)
        for (std::size_t i = 0; i < buf.size(); i += d.bytes) std::reverse(buf.begin() + i, buf.begin() + i + d.bytes);

    return splitFrames(d, buf.data(), layout.dims, layout.spacingMm, layout.frames, 1.0, 0.0, keep);
}

void writeNifti(const std::string& path, const ScalarImage& img, const std::string& dtype) {
    writeFrames(path, std::span<const ScalarImage>(&img, 1), dtype, false);
}

void writeNifti4d(const std::string& path, const std::vector<ScalarImage>& frames, const std::string& dtype) {
    writeFrames(path, frames, dtype, true);
}

}  // namespace bop::shape
