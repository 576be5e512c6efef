#include "app/scene/PieceSeeds.hpp"

#include "core/ConstructionSteps.hpp"
#include "shape/Components.hpp"

#include <map>
#include <sstream>

namespace bop::app {
namespace {

// Seed positions (voxel coordinates) of every piece of a species, largest piece first; the
// sizes of the pieces in voxels.
struct SpeciesPieces {
    std::vector<Eigen::Vector3d> positionVoxels;
    std::vector<std::size_t> sizes;
};

SpeciesPieces piecesOf(const core::Model& model, const GradientMap& m, const core::ConstructionParams& params,
                       int species) {
    const shape::Components c = shape::findComponents(
        m.dims(), [&](std::size_t v) { return m.occ[v] == species; }, shape::Neighbours::All);
    SpeciesPieces out;
    out.sizes = c.sizes;
    const double h = voxelLength(m.r0Voxels);
    for (const auto& choice : core::seedsOfPieces(params, model, m, species, c.label, std::uint32_t(c.sizes.size())))
        if (choice) out.positionVoxels.push_back(choice->pos / h);
    return out;
}

std::string note(const core::Model& model, int species, const SpeciesPieces& p) {
    std::ostringstream out;
    out << model.species[std::size_t(species)].name << ": " << p.sizes.size() << " pieces, one seed in each (";
    for (std::size_t k = 0; k < p.sizes.size() && k < 8; ++k) out << (k ? ", " : "") << p.sizes[k];
    out << (p.sizes.size() > 8 ? ", ..." : "") << " voxels)";
    return out.str();
}

}  // namespace

bool hasDefaultSeed(const std::vector<core::ConstructionEvent>& timeline) {
    for (const auto& e : timeline)
        if (e.action == core::ConstructionEvent::Action::Seed && !e.positionVoxels) return true;
    return false;
}

PieceSeeding seedEveryPiece(const core::Model& model, const GradientMap& map, const core::ConstructionParams& params,
                            const std::vector<core::ConstructionEvent>& timeline) {
    PieceSeeding out;
    std::map<int, SpeciesPieces> pieces;  // per species, found once
    for (const auto& e : timeline) {
        const bool expand = e.action == core::ConstructionEvent::Action::Seed && !e.positionVoxels && e.species >= 1 &&
                            e.species <= model.speciesCount();
        if (!expand) {
            out.timeline.push_back(e);
            continue;
        }
        auto found = pieces.find(e.species);
        if (found == pieces.end()) {
            found = pieces.emplace(e.species, piecesOf(model, map, params, e.species)).first;
            if (found->second.sizes.size() > 1) out.notes.push_back(note(model, e.species, found->second));
        }
        if (found->second.positionVoxels.empty()) {
            out.timeline.push_back(e);  // no voxels: the run says so when it seeds
            continue;
        }
        for (const Eigen::Vector3d& x : found->second.positionVoxels) {
            core::ConstructionEvent seed = e;
            seed.positionVoxels = x;
            out.timeline.push_back(seed);
        }
    }
    return out;
}

}  // namespace bop::app
