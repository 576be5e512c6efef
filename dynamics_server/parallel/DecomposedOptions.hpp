#pragma once
// What a decomposed run starts from besides the model and the particles (no <mpi.h> here, so
// tools outside parallel/ can fill it in).
#include "core/Construction.hpp"
#include "shape/GradientMapCrop.hpp"

#include <functional>
#include <optional>

namespace bop::parallel {

// Where a rank gets its window of the gradient map: the whole map's grid and r0 (arrays
// empty) and a function returning any window of any of its keyframes (bop-server reads them
// from the cache file).
struct MapSource {
    GradientMap header;
    std::function<GradientMap(int frame, const shape::VoxelWindow&)> crop;
    int frames = 1;  // keyframes (the model's schedule says when each is in force)
};

struct DecomposedOptions {
    std::optional<core::Construction> construction;  // timeline and parameters; none: no timeline
    long long firstStep = 0;                          // step number of the initial state
    std::optional<MapSource> map;                     // none: windows of model->map (kept whole)
};

}  // namespace bop::parallel
