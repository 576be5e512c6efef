#pragma once
// A small keyframed scene for tests: a 2-frame 4D NIfTI of a ball whose radius grows from 6 to 9
// voxels (24^3 voxels of 1 mm, r0 = 2 voxels), with [keyframes] cycling it every
// `frameDuration` time units from start 0, and `extra` TOML appended.
#include <string>

namespace bop::test {

// A construction timeline: both species seeded and growing from step 0 (TOML, for `extra`).
extern const char* const kGrowFromSeeds;

std::string writeKeyframeScene(const std::string& dir, double frameDuration, bool blend, const std::string& extra = "");

}  // namespace bop::test
