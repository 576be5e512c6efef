#pragma once
// Default display colours of bag species (r, g, b in [0, 1]): bag k's surface species 2k - 1 and
// volume species 2k get the k-th pair, the surface warm and light, the volume cool, so that eight
// bags side by side differ from one another and each bag's sheet from its fill. The scene's own
// colours (a label table's, a [species] table's) override them.
#include <array>

namespace bop {

inline std::array<float, 3> defaultSpeciesColour(int species) {
    static constexpr std::array<float, 3> surface[] = {
        {0.92f, 0.47f, 0.12f}, {0.78f, 0.16f, 0.63f}, {0.90f, 0.78f, 0.16f}, {0.86f, 0.24f, 0.24f},
        {0.95f, 0.60f, 0.72f}, {0.62f, 0.42f, 0.22f}, {0.98f, 0.66f, 0.40f}, {0.70f, 0.70f, 0.72f}};
    static constexpr std::array<float, 3> volume[] = {
        {0.31f, 0.59f, 0.90f}, {0.24f, 0.75f, 0.47f}, {0.59f, 0.43f, 0.90f}, {0.16f, 0.75f, 0.78f},
        {0.60f, 0.72f, 0.22f}, {0.26f, 0.32f, 0.68f}, {0.20f, 0.52f, 0.45f}, {0.42f, 0.45f, 0.52f}};
    const int bag = species > 0 ? (species - 1) / 2 : 0;
    return species % 2 ? surface[bag % 8] : volume[bag % 8];
}

}  // namespace bop
