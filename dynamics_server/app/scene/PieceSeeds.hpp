#pragma once
// A bag of several pieces built by birth and death (paper §3.6, docs/physics.md §7.4): births grow
// from particles already there, so a piece without a seed of its own stays empty. A seed event
// that gives no position becomes one seed per piece of its species' voxels, each at the voxel the
// default seed would choose within that piece (core::seedsOfPieces). Pieces are 26-connected
// (shape/Components.hpp): a surface shell one voxel thick is one piece even where it steps
// diagonally, and a hollow part's inner and outer shells are two.
#include "core/Construction.hpp"
#include "core/Model.hpp"

#include <string>
#include <vector>

namespace bop::app {

struct PieceSeeding {
    std::vector<core::ConstructionEvent> timeline;  // the events, default seeds one per piece
    std::vector<std::string> notes;                 // per species of several pieces: how many, their sizes
};

// `map`: the whole map. Seeds with a position, birth switches and species without voxels (the
// run then reports them) are kept as they are; the timeline's order is kept.
PieceSeeding seedEveryPiece(const core::Model& model, const GradientMap& map, const core::ConstructionParams& params,
                            const std::vector<core::ConstructionEvent>& timeline);

// Whether the timeline has a seed event without a position.
bool hasDefaultSeed(const std::vector<core::ConstructionEvent>& timeline);

}  // namespace bop::app
