#pragma once
// A rank's window of the gradient-map cache file (GradientMapFile.hpp), read straight from disk
// so that no rank ever holds the whole map: under MPI each rank keeps only its subdomain plus a
// margin (docs/parallel.md, GradientMapCrop.hpp). The view keeps the path, the per-frame header
// fields and the byte offsets of each frame's arrays; every crop opens the file afresh.
#include "bop/common/GradientMap.hpp"
#include "bop/common/GradientMapCrop.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bop::shape {

class GradientMapFileView {
public:
    // nullopt if the file is absent or was made for another key (a stale cache). Checks the
    // magic, the version and the trailing checksum (streamed in chunks: one pass over the file in
    // bounded memory) and walks the frame headers. bop::Error naming the file if it is truncated,
    // corrupt or inconsistent, as readGradientMaps.
    static std::optional<GradientMapFileView> open(const std::string& path, std::uint64_t key);

    int frames() const { return int(frames_.size()); }
    const std::string& path() const { return path_; }

    // Frame `frame` without its arrays: grid (whole dims, origin mm, voxel mm), r0Voxels, bagCount.
    GradientMap header(int frame) const;

    // The window of frame `frame`, equal field by field to cropGradientMap(whole map, window).
    // Reads the window's occ and nearest rows and the surface records they name, so about the
    // window's share of the file (see the .cpp). bop::Error naming the file if a nearest index
    // or a surface record is out of range, or the file changed since open(); std::out_of_range
    // for a bad frame, std::invalid_argument for a window outside the map. bytesRead, if given,
    // receives the bytes read from the file.
    GradientMap crop(int frame, const VoxelWindow& window, std::uint64_t* bytesRead = nullptr) const;

private:
    struct Frame {
        GradientMap header;  // arrays empty
        std::uint64_t surfaceCount = 0;
        std::uint64_t occAt = 0, nearestAt = 0, surfaceAt = 0;  // byte offsets in the file
    };
    GradientMapFileView() = default;
    const Frame& frame(int f) const;

    std::string path_;
    std::uint64_t key_ = 0, size_ = 0;  // to notice a file replaced after open()
    std::vector<Frame> frames_;
};

}  // namespace bop::shape
