#pragma once
// A cluster-pair prototype (the layout GROMACS's CPU kernels use), to measure whether it would
// beat BoP's Verlet-list loops by the margin that would justify building it: particles grouped
// four at a time by space, every pair of two listed clusters computed in the sixteen float lanes
// of one V16F (core/SimdMath.hpp) with no gathers, each i particle's values repeated four times
// and each j cluster's four values tiled four times, so that lane 4a + b pairs i-particle a with
// j-particle b. Forces and torques are summed in float: a prototype for timing, not for use.
#include "core/Potentials.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace bop::tools {

constexpr int kCluster = 4;  // particles per cluster; 4 x 4 pairs fill one V16F

struct ClusterSet {
    std::size_t clusters = 0;
    std::vector<std::int64_t> particle;  // cluster slot (4 c + a) -> particle index, -1 for padding
    // Per cluster, 16 floats each: x, y, z and the normal, each particle repeated four times
    // (i side) and the four particles tiled four times (j side).
    std::vector<float> iPos[3], jPos[3], iNormal[3], jNormal[3];
    // The half list: cluster pairs (i, j >= i, shift) whose bounding boxes come within the range.
    struct Entry {
        std::uint32_t j;
        float shift[3];  // added to the j positions (a periodic image), length
        bool self;       // j == i without a shift: only lanes a < b count
    };
    std::vector<std::uint32_t> start;  // entries of cluster i: [start[i], start[i + 1])
    std::vector<Entry> entries;
};

// Clusters of the particles in the box [lo, hi] (lengths in simulation units), periodic on every
// axis or on none: columns in x and y about one cluster wide (1.1 times a cube's edge at the
// particles' density), each column's particles sorted by z
// and taken four at a time; listed pairs within `range` (cutoff + skin) of each other's boxes.
ClusterSet buildClusters(const std::vector<Eigen::Vector3d>& pos, const std::vector<Eigen::Vector3d>& normal,
                         const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, bool periodic, double range);

struct ClusterPass {
    double seconds = 0;        // best of the timed passes, wall time of one core
    std::size_t computed = 0;  // pairs computed per pass (16 per cluster pair)
    std::size_t inRange = 0;   // of them within the cutoff (each unordered pair once)
    double checksum = 0;       // sum of the force components (keeps the work live; compare passes)
};

// One pass over the list of the LJ force (LjForm::forceOverR in float) within its cutoff, or of
// the oriented terms (OrientedTerms.hpp in float, one set of weights of 1, no curvature) within
// the weight's cutoff; each timed `repeats` times, the best kept.
ClusterPass ljClusterPass(const ClusterSet& set, const core::LjForm& lj, int repeats);
ClusterPass orientedClusterPass(const ClusterSet& set, const core::OrientedWeight& w, int repeats);

}  // namespace bop::tools
