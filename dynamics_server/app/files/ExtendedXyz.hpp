#pragma once
// Particle snapshots in extended XYZ, the text format OVITO and ASE read. A file is a trajectory:
// frames back to back, each a count line, a key=value comment line and one line per particle.
//
// Comment line written (one line):
//   Lattice="Lx 0 0 0 Ly 0 0 0 Lz" Origin="x y z" BoxHi="x y z"
//   Properties=type:S:1:pos:R:3:velo:R:3:normal:R:3:orientation:R:4:omega:R:3:id:I:1:Z:I:1
//   Time=t Step=s pbc="F F F"
// and, for a scene with a grid, LengthUnitMm (mm per simulation length unit); with materials also
// MassUnitKg, TimeUnitS, ForceUnitN and TimeS, the time in seconds (docs/physics.md §8).
// Numbers in %.17g, so reading a file back gives the state bit for bit (BoxHi keeps the upper box
// corner exact; Lattice and Origin are what OVITO and ASE use for the cell). The columns follow
// the extended XYZ specification (github.com/libAtoms/extxyz) and what its readers do with them:
//   - the species name is `type` (a simple string): OVITO makes it the Particle Type by name; ASE
//     keeps it as the array "type". Not `species`, which ASE takes for chemical symbols and
//     refuses for any other name;
//   - the species number is `Z`: ASE's atomic numbers (so ASE reads the file; the "element" it
//     shows is the species number's), an integer property "Z" in OVITO;
//   - `id` counts from 1 (core/Construction.hpp): OVITO's Particle Identifier takes it as a signed
//     64-bit integer, ASE 3.22 as a 32-bit one (right for the first 2^31 - 1 ids); the writer
//     refuses an id of 2^63 or more;
//   - orientation is the quaternion in OVITO's order x y z w (OVITO maps `orientation` to its
//     Orientation property, components X Y Z W), so aspherical particles render correctly.
// Files of earlier versions (names in `species`, numbers in `species_number`, births with ids
// above 2^63) read as before, such an id with bit 62 in place of bit 63.
#include "bop/common/UnitSystem.hpp"
#include "core/Command.hpp"
#include "core/Particles.hpp"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

namespace bop::app {

struct XyzFrameInfo {
    long long step = 0;
    double time = 0;                                  // simulation time units
    Eigen::Vector3d boxLo = Eigen::Vector3d::Zero();  // simulation box, simulation length units
    Eigen::Vector3d boxHi = Eigen::Vector3d::Zero();
    std::array<bool, 3> periodic{false, false, false};  // x y z
    // Checkpoints (docs/file-formats.md): the construction's state, so that a restart goes on as
    // the run would have. Births: one 0/1 per species number from 1; Seeds: seeds placed so far;
    // NextId: the id the next seed or birth takes.
    std::vector<char> births;  // empty: not recorded
    long long seeds = -1;      // -1: not recorded
    long long nextId = 0;      // the id the next new particle takes; 0: not recorded
    // Settle: where a placed bag's settling is (app/runs/Settling.hpp), words without quotes;
    // empty: not recorded.
    std::string settle;
    // Cuts: the cuts made so far (core::CutCommand), seven numbers each (from, to, radius;
    // simulation length units), so that a restart edits the map as the run did. Empty: none.
    std::vector<core::CutCommand> cuts;
    // Yields: the voxels dents took out of their bags (core/Plasticity.hpp), each check's group as
    // its count, then its whole-map voxel indices in order. Empty: none.
    std::vector<std::vector<std::uint64_t>> yields;
    UnitSystem units;  // written where known (lengthKnown(), physical)
};

struct XyzFrame {
    core::Particles particles;
    XyzFrameInfo info;
};

// Writes one frame. speciesNames: index = species number; every species number in p must have a
// non-empty name without whitespace or quotes (else bop::Error("extended XYZ output", ...)).
void writeExtendedXyz(std::ostream& os, const core::Particles& p, const std::vector<std::string>& speciesNames,
                      const XyzFrameInfo& info);

// Appends one frame to the trajectory file at path (created if missing). Errors:
// bop::Error(path, "cannot write: ...") (and bad species names are reported before anything is written).
void appendExtendedXyz(const std::string& path, const core::Particles& p, const std::vector<std::string>& speciesNames,
                       const XyzFrameInfo& info);

// Reads frame `frame` (0-based; -1 = the last) of an extended XYZ file.
// Needs a `pos:R:3` column and species names (`type:S:1` or `species:S:1`, mapped with
// speciesNames) or, without them, species numbers (`Z:I:1`, `type:I:1` or `species_number:I:1`).
// Optional columns:
// velo:R:3, omega:R:3 (default 0), id:I:1 (default: the particle's index in the frame),
// orientation:R:4 (x y z w; the normal is recomputed as q e_z), else normal:R:3 (orientation =
// shortest-arc rotation from e_z to the normal), else identity. Other columns are skipped.
// Box: Origin and BoxHi, else Origin + the diagonal of Lattice (which must be orthogonal); pbc
// defaults to T T T with a Lattice and to F F F without one. Force and torque are zero.
// Every problem throws bop::Error(path, "line N: ... expected ...").
XyzFrame readExtendedXyz(const std::string& path, const std::vector<std::string>& speciesNames, int frame = -1);

}  // namespace bop::app
