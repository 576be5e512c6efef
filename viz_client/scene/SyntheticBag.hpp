#pragma once
// A torus bag made by placement rather than by the dynamics, for the renderer's tests and
// benchmarks: surface particles in rings about r0 apart on the torus (every other ring shifted
// half a step, like a triangulated sheet), volume particles on a cubic grid of spacing r0 inside
// it, kept 0.8 r0 within the surface. Species 1 is the surface, 2 the fill.
#include "codec/Messages.hpp"

namespace bop::viz {

// Major radius R and tube radius a, length; r0, length.
protocol::StateFrame torusBag(double R, double a, double r0);

// Scene info for it: the two species with these colours, the box around the torus.
protocol::SceneInfo torusBagScene(double R, double a, double r0, const std::array<std::uint8_t, 4>& surfaceRgba,
                                  const std::array<std::uint8_t, 4>& volumeRgba);

}  // namespace bop::viz
