#pragma once
// The bags of a scene as the viewer lists them (docs/viewer.md): a server built from a shape
// numbers bag k's species 2k - 1 (its surface, "<bag>-surface") and 2k (its volume,
// "<bag>-volume"), so the viewer groups species in those pairs, names each bag from its
// species' names, and hides or shows a bag as one. Species that are not such a pair (a bulk box,
// a hand-written table) stay alone, each a "bag" of one species. No OpenGL or ImGui here.
#include "codec/Messages.hpp"
#include "scene/Instances.hpp"

#include <string>
#include <vector>

namespace bop::viz {

struct BagEntry {
    std::string name;
    std::vector<int> species;  // species numbers (1-based): surface first, then volume
};

// The scene's bags, in species order.
std::vector<BagEntry> bagsOfScene(const protocol::SceneInfo& scene);

// Particles of the bag in a frame, given counts by species number (index 0 unused).
std::size_t bagParticles(const BagEntry& bag, const std::vector<std::size_t>& perSpecies);

// Whether every species of the bag is hidden; hide or show all of them.
bool bagHidden(const ViewFilter& view, const BagEntry& bag);
void setBagHidden(ViewFilter& view, const BagEntry& bag, bool hidden);

// Hides the bags (or single species) of these names; returns the names that matched nothing.
std::vector<std::string> hideByName(ViewFilter& view, const protocol::SceneInfo& scene,
                                    const std::vector<std::string>& names);

}  // namespace bop::viz
