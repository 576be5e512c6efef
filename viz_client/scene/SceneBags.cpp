#include "scene/SceneBags.hpp"

#include <algorithm>

namespace bop::viz {
namespace {

// "liver-surface" -> "liver" when the name ends in the suffix; empty otherwise.
std::string stem(const std::string& name, const std::string& suffix) {
    if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        return {};
    return name.substr(0, name.size() - suffix.size());
}

}  // namespace

std::vector<BagEntry> bagsOfScene(const protocol::SceneInfo& scene) {
    std::vector<BagEntry> bags;
    const int n = int(scene.species.size());
    for (int k = 1; k <= n;) {
        const protocol::SpeciesInfo& a = scene.species[std::size_t(k - 1)];
        if (k + 1 <= n && k % 2 == 1) {
            const protocol::SpeciesInfo& b = scene.species[std::size_t(k)];
            const std::string name = stem(a.name, "-surface");
            if (a.kind == protocol::SpeciesKind::Surface && b.kind == protocol::SpeciesKind::Volume && !name.empty() &&
                name == stem(b.name, "-volume")) {
                bags.push_back({name, {k, k + 1}});
                k += 2;
                continue;
            }
        }
        bags.push_back({a.name, {k}});
        ++k;
    }
    return bags;
}

std::size_t bagParticles(const BagEntry& bag, const std::vector<std::size_t>& perSpecies) {
    std::size_t n = 0;
    for (int s : bag.species)
        if (std::size_t(s) < perSpecies.size()) n += perSpecies[std::size_t(s)];
    return n;
}

bool bagHidden(const ViewFilter& view, const BagEntry& bag) {
    return std::all_of(bag.species.begin(), bag.species.end(), [&](int s) {
        return std::size_t(s) < view.hiddenSpecies.size() && view.hiddenSpecies[std::size_t(s)];
    });
}

void setBagHidden(ViewFilter& view, const BagEntry& bag, bool hidden) {
    for (int s : bag.species) {
        if (std::size_t(s) >= view.hiddenSpecies.size()) view.hiddenSpecies.resize(std::size_t(s) + 1, false);
        view.hiddenSpecies[std::size_t(s)] = hidden;
    }
}

std::vector<std::string> hideByName(ViewFilter& view, const protocol::SceneInfo& scene,
                                    const std::vector<std::string>& names) {
    std::vector<std::string> unknown;
    const std::vector<BagEntry> bags = bagsOfScene(scene);
    for (const std::string& name : names) {
        bool found = false;
        for (const BagEntry& b : bags)
            if (b.name == name) setBagHidden(view, b, true), found = true;
        for (std::size_t k = 0; k < scene.species.size(); ++k)
            if (scene.species[k].name == name) setBagHidden(view, {name, {int(k) + 1}}, true), found = true;
        if (!found) unknown.push_back(name);
    }
    return unknown;
}

}  // namespace bop::viz
