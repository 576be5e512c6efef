#pragma once
// Exact Euclidean distance transform with feature (nearest-site) output on an isotropic voxel
// grid, in linear time: one scan per row along x, then the lower envelope of parabolas
// (Felzenszwalb & Huttenlocher) along y and along z. docs/physics.md §4.3(b).
#include "Volume.hpp"

#include <cstdint>
#include <vector>

namespace bop {

inline constexpr std::int32_t kNoSite = -1;

// feature: in: a site label (>= 0) on every site voxel, kNoSite elsewhere.
//          out: the label of a nearest site (ties pick either), kNoSite if there are no sites.
// dist2:   out: squared distance to that site, in voxels^2 (exact integers); INT32_MAX if none.
// threads: 0 = OpenMP default; 1 = one core.
void exactDistanceTransform(const Dims& dims, std::vector<std::int32_t>& feature, std::vector<std::int32_t>& dist2,
                            int threads = 0);

}  // namespace bop
