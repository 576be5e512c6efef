#pragma once
// How the simulation box is cut into one subdomain per rank (no MPI here, so it is unit-tested
// on its own): a Cartesian grid of ranks, and per axis the cut planes between them. Cuts start
// uniform and move so that ranks hold similar particle counts (the paper gave every CPU an equal
// sub-volume and its slowest CPU set the frame rate, §5.1). Planes along one axis are shared by
// the whole grid (a rectilinear decomposition), so a rank's neighbours are the 6 face neighbours.
//
// Lengths in simulation units (r0 = sqrt(3)).
#include "core/Model.hpp"

#include <array>
#include <vector>

namespace bop::parallel {

using Coords = std::array<int, 3>;

class Decomposition {
public:
    // Uniform cuts of box into dims[0] x dims[1] x dims[2] subdomains. minWidth: the narrowest
    // allowed subdomain (the halo range: a halo then never reaches past a face neighbour);
    // std::invalid_argument names the axis when the box is too small for the grid.
    Decomposition(const core::Box& box, Coords dims, double minWidth);

    const core::Box& box() const { return box_; }
    const Coords& dims() const { return dims_; }
    int rankCount() const { return dims_[0] * dims_[1] * dims_[2]; }
    const std::vector<double>& cuts(int axis) const { return cuts_[std::size_t(axis)]; }  // dims + 1 planes

    // The subdomain at grid coordinates c: [lo, hi) per axis; periodic flags are those of the
    // box on axes with one rank and false elsewhere (images across split axes come as halos).
    core::Box subdomain(const Coords& c) const;
    // Grid coordinates of the subdomain that owns position x (wrapped into a periodic box first;
    // outside a non-periodic box, the nearest subdomain).
    Coords owner(const Eigen::Vector3d& x) const;

    // Moves the cut planes of each axis to the quantiles of the particle counts in `histogram`
    // (per axis, equal bins across the box), keeping every subdomain at least minWidth wide.
    void balance(const std::array<std::vector<double>, 3>& histogram);
    // Largest rank count over the mean, for per-rank counts (1 = perfect balance).
    static double imbalance(const std::vector<double>& countsPerRank);

private:
    core::Box box_;
    Coords dims_;
    double minWidth_;
    std::array<std::vector<double>, 3> cuts_;
};

// Counts of particles per rank (in rank order) under a decomposition.
std::vector<double> countsPerRank(const Decomposition& d, const std::vector<Eigen::Vector3d>& pos);
// Rank number of grid coordinates, z fastest: the numbering of MPI_Cart_create without reordering.
int rankOf(const Coords& c, const Coords& dims);
Coords coordsOf(int rank, const Coords& dims);

}  // namespace bop::parallel
