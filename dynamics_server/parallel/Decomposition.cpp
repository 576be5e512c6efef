#include "Decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::parallel {
namespace {

const char* kAxis[3] = {"x", "y", "z"};

}  // namespace

Decomposition::Decomposition(const core::Box& box, Coords dims, double minWidth)
    : box_(box), dims_(dims), minWidth_(minWidth) {
    for (int a = 0; a < 3; ++a) {
        const int n = dims_[std::size_t(a)];
        if (n < 1) throw std::invalid_argument(std::string("rank grid: ") + kAxis[a] + " needs at least one rank");
        const double L = box.hi[a] - box.lo[a];
        if (n > 1 && L < n * minWidth)
            throw std::invalid_argument(std::string("rank grid: ") + std::to_string(n) + " ranks along " + kAxis[a] +
                                        " need the box at least " + std::to_string(n * minWidth) +
                                        " wide (one halo range each), it is " + std::to_string(L) +
                                        ": use fewer ranks");
        auto& c = cuts_[std::size_t(a)];
        c.resize(std::size_t(n) + 1);
        for (int k = 0; k <= n; ++k) c[std::size_t(k)] = box.lo[a] + L * k / n;
        c.back() = box.hi[a];
    }
}

core::Box Decomposition::subdomain(const Coords& c) const {
    core::Box b;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = cuts_[std::size_t(a)][std::size_t(c[std::size_t(a)])];
        b.hi[a] = cuts_[std::size_t(a)][std::size_t(c[std::size_t(a)]) + 1];
        b.periodic[std::size_t(a)] = box_.periodic[std::size_t(a)] && dims_[std::size_t(a)] == 1;
    }
    return b;
}

Coords Decomposition::owner(const Eigen::Vector3d& x) const {
    Coords c{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        double u = x[a];
        const double L = box_.hi[a] - box_.lo[a];
        if (box_.periodic[std::size_t(a)]) u -= L * std::floor((u - box_.lo[a]) / L);
        const auto& cut = cuts_[std::size_t(a)];
        // The last plane at or below u (interior planes only), so [cut_k, cut_k+1) belongs to k.
        const auto it = std::upper_bound(cut.begin() + 1, cut.end() - 1, u);
        c[std::size_t(a)] = int(it - (cut.begin() + 1));
    }
    return c;
}

void Decomposition::balance(const std::array<std::vector<double>, 3>& histogram) {
    for (int a = 0; a < 3; ++a) {
        const int n = dims_[std::size_t(a)];
        const auto& h = histogram[std::size_t(a)];
        if (n == 1 || h.empty()) continue;
        const double lo = box_.lo[a], L = box_.hi[a] - box_.lo[a], bin = L / double(h.size());
        double total = 0;
        for (double v : h) total += v;
        if (total <= 0) continue;
        auto& cut = cuts_[std::size_t(a)];
        // Plane k at the coordinate where the cumulative count reaches k/n of the total
        // (linear within a bin), then pushed apart to minWidth from both ends.
        double cumulative = 0;
        std::size_t b = 0;
        for (int k = 1; k < n; ++k) {
            const double target = total * k / n;
            while (b < h.size() && cumulative + h[b] < target) cumulative += h[b++];
            const double within = b < h.size() && h[b] > 0 ? (target - cumulative) / h[b] : 0.0;
            cut[std::size_t(k)] = lo + bin * (double(b) + within);
        }
        for (int k = 1; k < n; ++k)
            cut[std::size_t(k)] = std::max(cut[std::size_t(k)], cut[std::size_t(k) - 1] + minWidth_);
        for (int k = n - 1; k >= 1; --k)
            cut[std::size_t(k)] = std::min(cut[std::size_t(k)], cut[std::size_t(k) + 1] - minWidth_);
    }
}

double Decomposition::imbalance(const std::vector<double>& counts) {
    double sum = 0, most = 0;
    for (double c : counts) {
        sum += c;
        most = std::max(most, c);
    }
    return sum > 0 ? most * double(counts.size()) / sum : 1.0;
}

int rankOf(const Coords& c, const Coords& dims) {
    return (c[0] * dims[1] + c[1]) * dims[2] + c[2];
}

Coords coordsOf(int rank, const Coords& dims) {
    return {rank / (dims[1] * dims[2]), (rank / dims[2]) % dims[1], rank % dims[2]};
}

std::vector<double> countsPerRank(const Decomposition& d, const std::vector<Eigen::Vector3d>& pos) {
    std::vector<double> counts(std::size_t(d.rankCount()), 0.0);
    for (const auto& x : pos) counts[std::size_t(rankOf(d.owner(x), d.dims()))] += 1;
    return counts;
}

}  // namespace bop::parallel
