#pragma once
// Checkpoints: every particle and the construction's state as one extended XYZ frame
// (docs/file-formats.md), written atomically (a temporary file, fsync, rename) so that a crash
// leaves the previous checkpoint whole. `bop-server --restart FILE` goes on from one at any rank
// count; from a periodic one at the same rank count, bit for bit as the run went on from it.
#include "app/files/ExtendedXyz.hpp"
#include "core/Construction.hpp"
#include "core/Model.hpp"
#include "core/Particles.hpp"

#include <string>

namespace bop::app {

// The header of a snapshot of `model`'s box at `step` (time = step x dt): what final.xyz,
// trajectories and checkpoints carry.
XyzFrameInfo snapshotInfo(const core::Model& model, long long step);

// all: every particle of the run (sorted by id, as a decomposed run gathers them).
// bop::Error naming the file when it cannot be written.
// settle: the settling's state (app/runs/Settling.hpp), empty when the run does not settle;
// cuts, yields: the cuts made and the dents yielded so far (Simulation::cuts, ::yields), so that a
// restart edits the map alike.
void writeCheckpoint(const std::string& path, const core::Particles& all, const core::Model& model,
                     const core::Construction& construction, long long step, const std::string& settle = {},
                     const std::vector<core::CutCommand>& cuts = {},
                     const std::vector<std::vector<std::uint64_t>>& yields = {});

}  // namespace bop::app
