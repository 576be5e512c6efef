#pragma once
// Particles in the neighbour list's order (docs/dynamics.md, "Particle order"): the box cut into
// the list's cells (CellList.hpp: cells at least the list's range wide, numbered with the axis of
// fewest cells varying fastest), the particles sorted by cell, then by id within a cell. The pair
// loops walk the list's entries in that order, so the gathers from the particles into the entries
// and the forces folded back stream through memory rather than jump, and so do the integrator and
// the map forces over neighbours; the cost per particle then does not grow with the bag. Sorting
// by (cell, id) gives an order that depends on the positions and ids alone, not on the order
// before. (A Hilbert curve over cells of r0 was measured slower, docs/dynamics.md: it keeps
// neighbours near in memory too, but in an order other than the loops'.)
#include "Model.hpp"
#include "Particles.hpp"

#include <cstdint>
#include <vector>

namespace bop::core {

// The order that sorts the particles by (cell of width at least `cell` over `box`, id); positions
// outside the box count in its border cells. cell: length units, positive.
std::vector<std::uint32_t> spatialOrder(const Box& box, double cell, const std::vector<Eigen::Vector3d>& pos,
                                        const std::vector<std::uint64_t>& id);

// Every array of p in that order: p's particle k becomes the old particle order[k].
void reorder(Particles& p, const std::vector<std::uint32_t>& order);

}  // namespace bop::core
