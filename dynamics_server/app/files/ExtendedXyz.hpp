#pragma once
// Particle snapshots in extended XYZ, the text format OVITO and ASE read. A file is a trajectory:
// frames back to back, each a count line, a key=value comment line and one line per particle.
//
// Comment line written (one line):
//   Lattice="Lx 0 0 0 Ly 0 0 0 Lz" Origin="x y z" BoxHi="x y z"
//   Properties=species:S:1:pos:R:3:velo:R:3:normal:R:3:orientation:R:4:omega:R:3:id:I:1:species_number:I:1
//   Time=t Step=s pbc="F F F"
// Numbers in %.17g, so reading a file back gives the state bit for bit (BoxHi keeps the upper box
// corner exact; Lattice and Origin are what OVITO and ASE use for the cell).
// Column conventions follow OVITO's extended XYZ importer:
//   - orientation is the quaternion in OVITO's order x y z w (OVITO maps `orientation` to its
//     Orientation property, components X Y Z W), so aspherical particles render correctly;
//   - the integer species number is `species_number`, not `type`: OVITO maps both `species`
//     and `type` to Particle Type and refuses a file that has both columns.
// ASE builds Atoms from `species`, so it reads these files only when the species names are
// chemical symbols (ASE capitalizes them and looks them up in its element table).
#include "core/Particles.hpp"

#include <Eigen/Core>

#include <array>
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
    // the run would have. Births: one 0/1 per species number from 1; Seeds: seeds placed so far.
    std::vector<char> births;  // empty: not recorded
    long long seeds = -1;      // -1: not recorded
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
// Needs a `pos:R:3` column and `species:S:1` (names mapped with speciesNames) or, without it, an
// integer `type:I:1` or `species_number:I:1` column (species numbers). Optional columns:
// velo:R:3, omega:R:3 (default 0), id:I:1 (default: the particle's index in the frame),
// orientation:R:4 (x y z w; the normal is recomputed as q e_z), else normal:R:3 (orientation =
// shortest-arc rotation from e_z to the normal), else identity. Other columns are skipped.
// Box: Origin and BoxHi, else Origin + the diagonal of Lattice (which must be orthogonal); pbc
// defaults to T T T with a Lattice and to F F F without one. Force and torque are zero.
// Every problem throws bop::Error(path, "line N: ... expected ...").
XyzFrame readExtendedXyz(const std::string& path, const std::vector<std::string>& speciesNames, int frame = -1);

}  // namespace bop::app
