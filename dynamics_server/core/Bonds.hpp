#pragma once
// A bonded elastic volume (docs/physics.md §8.3): the particles of one bag that were neighbours as
// placed are joined by springs at their placed distances, and each particle carries a volume term
// on the mean stretch of its bonds, so that a bag whose species have a bond stiffness is an elastic
// solid whose rest shape is the placement. The network is fixed at the start (every process builds
// the same one, by global id); a bond pulls while its length is within `cut` (the pair cutoff, so
// that a partner owned elsewhere is always among the ghosts) and lets go beyond it.
//
// Energy of bond ij, k_ij (l - L)^2 / 2, with k_ij = k min(1, (r0 / L)^4): on the fcc lattice the
// second neighbours' springs are a quarter of the first's, which makes the lattice isotropic
// (lambda = mu = k / (sqrt 2 r0)). Energy of particle i, B v theta_i^2 / 2, with
// theta_i = sum_j a_ij (l_ij - L_ij) the trace of the strain that fits its bonds' stretches best
// (least squares over the placed bonds, a_ij fixed at the start): exact for an affine deformation
// whatever the neighbourhood (a sheet particle has bonds on one side only), so that B adds to the
// bulk modulus and nothing to the shear modulus.
#include "Model.hpp"
#include "Particles.hpp"

#include <cstdint>
#include <vector>

namespace bop::core {

struct Halo;

// Second neighbours of the fcc lattice lie at sqrt 2 r0, third at sqrt 3 r0: placed neighbours
// closer than this are bonded, multiples of r0.
inline constexpr double kBondReachR0 = 1.5;

struct BondNetwork {
    // By global id: the bonds of particle `id` are entries [start[id], start[id + 1]).
    std::vector<std::uint32_t> start;
    std::vector<std::uint64_t> partner;  // global id of the other particle
    std::vector<double> rest;            // L, length units
    std::vector<double> stiffness;       // k_ij, energy / length^2
    // a_ij of the entry's own particle and a_ji of its partner, 1 / length.
    std::vector<double> trace, traceAtPartner;
    std::vector<double> bulkVolume;  // per id: B_i v, energy
    // Per id: where the particle was placed (a support's anchor, the bond's rest ends a cut is
    // checked against) and its support's spring, energy / length^2 (0: not anchored).
    std::vector<Eigen::Vector3d> anchor;
    std::vector<double> anchorStiffness;
    double cut = 0;  // a bond pulls while its length is at most this, length units

    std::size_t bonds() const { return partner.size() / 2; }  // each bond is listed at both ends
    std::uint64_t idLimit() const { return start.empty() ? 0 : start.size() - 1; }
};

struct Params;

// Whether any species is bonded (Species::bondStiffness above 0).
bool hasBonds(const Model& model);
// The length within which a bond pulls: the neighbour list's cutoff (its range less the skin), so
// that a partner owned by another process is a ghost. Length units.
double bondCut(const Model& model, const Params& params);

// Whether the bags of species a and b are joined by bonds: one bag, or one held directly in the
// other (GradientMap::bagParent; empty: the paper's chain of nested bags). Bags side by side touch
// and slide.
bool bondedBags(const std::vector<std::uint8_t>& bagParent, int a, int b);

// Bonds between the particles of `placed` closer than kBondReachR0 r0 whose bags are joined
// (bondedBags) and whose species have Species::bondStiffness above 0; across two bags the two
// springs in series. cut: length units. supportBelow (length units; 0: none): the bonded particles
// placed within this height of the lowest are anchored there by kAnchorBonds of their bonds. The
// same network on every process given the same particles.
BondNetwork buildBonds(const Model& model, const Particles& placed, double cut,
                       const std::vector<std::uint8_t>& bagParent, double supportBelow = 0);

// The network less the bonds a blade of `radius` swept from `from` to `to` (length units) cuts:
// those whose placed ends' segment passes within the radius of the blade's. A function of the
// network and the cut alone, so that every process and a restart after the cut break the same.
// The count broken, if asked.
BondNetwork breakBonds(const BondNetwork& net, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
                       std::size_t* broken = nullptr);

// The shortest distance between the segments p0-p1 and q0-q1.
double segmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1);

// A support's anchor in nearest-neighbour bonds: stiff against the bag, far from the step's limit.
inline constexpr double kAnchorBonds = 10.0;

// The network's forces on this process's particles; ghosts' dilatations come from their owners.
class BondForces {
public:
    // theta_i of every particle here (index as in `p`). Bonds with a partner neither here nor among
    // the ghosts are longer than the cut (the halo's promise) and count as let go.
    void dilatation(const BondNetwork& net, const Particles& p, const Halo* halo, std::vector<double>& theta);
    // Adds the forces to p.force; `ghostTheta` the ghosts' dilatations in halo order. Returns this
    // process's share of the energy (a bond across processes counts half here) and adds to virial
    // (sum over bonds of r_ij . F_j, energy) its share.
    double add(const BondNetwork& net, Particles& p, const Halo* halo, const std::vector<double>& theta,
               const std::vector<double>& ghostTheta, double& virial);

private:
    void index(const BondNetwork& net, const Particles& p, const Halo* halo);
    std::vector<std::int64_t> where_;  // by id: index in p, or p.size() + ghost, or -1
    std::vector<std::uint64_t> filled_;
};

}  // namespace bop::core
