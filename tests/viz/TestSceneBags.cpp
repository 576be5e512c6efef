// The viewer's list of bags (viz_client/scene/SceneBags.hpp): species paired into bags by the
// server's numbering and names, a bag hidden as one, and --hide by name.
#include "scene/SceneBags.hpp"

#include <catch2/catch.hpp>

using namespace bop;
using namespace bop::viz;
using protocol::SpeciesKind;

namespace {

// The organs scene's species: four bags, each a surface and a volume species.
protocol::SceneInfo organs() {
    protocol::SceneInfo s;
    for (const char* bag : {"liver", "stomach", "spleen", "tumour"}) {
        s.species.push_back({std::string(bag) + "-surface", SpeciesKind::Surface, {200, 100, 50, 255}});
        s.species.push_back({std::string(bag) + "-volume", SpeciesKind::Volume, {120, 60, 30, 255}});
    }
    return s;
}

// A frame with `per[k]` particles of species k + 1.
protocol::StateFrame frameOf(const std::vector<int>& per) {
    protocol::StateFrame f;
    for (std::size_t k = 0; k < per.size(); ++k)
        for (int i = 0; i < per[k]; ++i) {
            const float x = float(f.species.size());
            f.positions.insert(f.positions.end(), {x, 0, 0});
            f.normals.insert(f.normals.end(), {0, 0, 1});
            f.species.push_back(std::uint8_t(k + 1));
        }
    f.frameParticleCount = std::uint32_t(f.species.size());
    return f;
}

}  // namespace

TEST_CASE("viewer bags: species pair into named bags, others stay alone", "[viz]") {
    const std::vector<BagEntry> bags = bagsOfScene(organs());
    REQUIRE(bags.size() == 4);
    CHECK(bags[1].name == "stomach");
    CHECK(bags[1].species == std::vector<int>{3, 4});
    CHECK(bags[3].species == std::vector<int>{7, 8});

    // A bulk box (one volume species) and a pair whose names do not match stay species.
    protocol::SceneInfo s;
    s.species = {{"bulk", SpeciesKind::Volume, {}},
                 {"a-surface", SpeciesKind::Surface, {}},
                 {"b-volume", SpeciesKind::Volume, {}}};
    const std::vector<BagEntry> alone = bagsOfScene(s);
    REQUIRE(alone.size() == 3);
    CHECK(alone[0].name == "bulk");
    CHECK(alone[2].species == std::vector<int>{3});
}

TEST_CASE("viewer bags: hiding a bag removes exactly its particles from the picture", "[viz]") {
    const protocol::SceneInfo s = organs();
    const protocol::StateFrame f = frameOf({30, 50, 12, 20, 9, 14, 4, 6});
    const std::vector<BagEntry> bags = bagsOfScene(s);
    ViewFilter view;
    Instances all, some;
    buildInstances(f, s, view, all);
    std::vector<std::size_t> per(9, 0);
    for (auto sp : f.species) ++per[sp];
    CHECK(bagParticles(bags[1], per) == 32);

    setBagHidden(view, bags[1], true);
    CHECK(bagHidden(view, bags[1]));
    CHECK_FALSE(bagHidden(view, bags[0]));
    buildInstances(f, s, view, some);
    CHECK(some.hidden == 32);
    CHECK(some.surfels.size() + some.spheres.size() == all.surfels.size() + all.spheres.size() - 32);
    CHECK(some.drawnPerSpecies[3] == 0);
    CHECK(some.drawnPerSpecies[4] == 0);
    CHECK(some.drawnPerSpecies[1] == 30);

    setBagHidden(view, bags[1], false);
    buildInstances(f, s, view, some);
    CHECK(some.hidden == 0);
}

TEST_CASE("viewer bags: --hide by bag or species name, unknown names returned", "[viz]") {
    const protocol::SceneInfo s = organs();
    ViewFilter view;
    const std::vector<std::string> unknown = hideByName(view, s, {"spleen", "liver-volume", "kidney"});
    CHECK(unknown == std::vector<std::string>{"kidney"});
    const std::vector<BagEntry> bags = bagsOfScene(s);
    CHECK(bagHidden(view, bags[2]));
    CHECK_FALSE(bagHidden(view, bags[0]));  // only its volume
    CHECK(view.hiddenSpecies[2]);
    CHECK_FALSE(view.hiddenSpecies[1]);
}
