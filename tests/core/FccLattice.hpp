#pragma once
// The displaced fcc lattice of the bulk-box tests (scripts/bench/step.sh's workload): `cells`^3
// cells at nearest distance r0 (lengths in simulation units), every site moved uniformly by up
// to 0.05 r0 per axis by a generator seeded with `seed`, sites in cell order.
#include "core/Model.hpp"

#include <Eigen/Core>

#include <cmath>
#include <random>
#include <vector>

namespace bop::test {

inline std::vector<Eigen::Vector3d> jitteredFcc(int cells, std::uint32_t seed) {
    const double a = std::sqrt(2.0) * kR0;  // cubic cell edge
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.05 * kR0, 0.05 * kR0);
    const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
    std::vector<Eigen::Vector3d> sites;
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j)
            for (int k = 0; k < cells; ++k)
                for (const auto& o : basis)
                    sites.push_back(Eigen::Vector3d(i + o[0], j + o[1], k + o[2]) * a +
                                    Eigen::Vector3d(u(rng), u(rng), u(rng)));
    return sites;
}

}  // namespace bop::test
