#include "Bonds.hpp"

#include "CellList.hpp"
#include "PairForces.hpp"
#include "Threads.hpp"
#include "bop/common/GradientMap.hpp"
#include "bop/common/Units.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace bop::core {
namespace {

// a_ij: the trace of the least-squares strain eps over i's bonds, from l - L = L n.eps.n.
void traceCoefficients(const Particles& placed, BondNetwork& net) {
    std::vector<Eigen::Vector3d> at(net.idLimit(), Eigen::Vector3d::Zero());
    for (std::size_t i = 0; i < placed.size(); ++i) at[placed.id[i]] = placed.pos[i];
    using Row = Eigen::Matrix<double, 6, 1>;
    const auto row = [&](std::uint64_t i, std::uint64_t j) {
        const Eigen::Vector3d r = at[j] - at[i];
        const Eigen::Vector3d n = r.normalized();
        Row a;
        a << n.x() * n.x(), n.y() * n.y(), n.z() * n.z(), 2 * n.x() * n.y(), 2 * n.x() * n.z(), 2 * n.y() * n.z();
        return Row(r.norm() * a);
    };
    Row trace;
    trace << 1, 1, 1, 0, 0, 0;
    net.trace.assign(net.partner.size(), 0.0);
    for (std::uint64_t id = 0; id < net.idLimit(); ++id) {
        if (net.start[id] == net.start[id + 1]) continue;
        Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) {
            const Row a = row(id, net.partner[b]);
            m += a * a.transpose();
        }
        // A light ridge: a neighbourhood that misses a strain component reads none of it rather
        // than a large one.
        m += 1e-3 * m.trace() / 6 * Eigen::Matrix<double, 6, 6>::Identity();
        const Row x = m.ldlt().solve(trace);
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) net.trace[b] = row(id, net.partner[b]).dot(x);
    }
    net.traceAtPartner.assign(net.trace.size(), 0.0);
    for (std::uint64_t id = 0; id < net.idLimit(); ++id)
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) {
            const std::uint64_t j = net.partner[b];
            const auto first = net.partner.begin() + net.start[j], last = net.partner.begin() + net.start[j + 1];
            net.traceAtPartner[b] = net.trace[std::size_t(std::lower_bound(first, last, id) - net.partner.begin())];
        }
}

}  // namespace

bool hasBonds(const Model& model) {
    for (const Species& s : model.species)
        if (s.bondStiffness > 0) return true;
    return false;
}

double bondCut(const Model& model, const Params& params) {
    return PairForces::listRange(model, params) - model.integration.skinR0 * bop::kR0;
}

bool bondedBags(const std::vector<std::uint8_t>& bagParent, int a, int b) {
    const int ba = bop::bagOfSpecies(a), bb = bop::bagOfSpecies(b);
    return ba == bb || bop::parentOfBag(bagParent, ba) == bb || bop::parentOfBag(bagParent, bb) == ba;
}

BondNetwork buildBonds(const Model& model, const Particles& placed, double cut,
                       const std::vector<std::uint8_t>& bagParent, double supportBelow) {
    const double reach = kBondReachR0 * bop::kR0, r0 = bop::kR0;
    const double volume = r0 * r0 * r0 / std::sqrt(2.0);  // an fcc site's, length^3
    const auto bonded = [&](std::size_t i) { return model.species[placed.species[i]].bondStiffness > 0; };
    std::uint64_t idLimit = 0;
    Box around;  // the placed particles' bounding box: cells of `reach` over it
    around.lo = around.hi = placed.size() ? placed.pos[0] : Eigen::Vector3d::Zero();
    for (std::uint32_t i = 0; i < placed.size(); ++i) {
        idLimit = std::max(idLimit, placed.id[i] + 1);
        around.lo = around.lo.cwiseMin(placed.pos[i]);
        around.hi = around.hi.cwiseMax(placed.pos[i]);
    }
    around.hi += Eigen::Vector3d::Constant(reach);
    CellList cells;
    cells.build(around, reach, placed.pos);
    struct Entry {
        std::uint64_t partner;
        double rest, stiffness;
    };
    std::vector<std::vector<Entry>> byId(idLimit);
    std::vector<CellList::Neighbour> near;
    for (std::uint32_t i = 0; i < placed.size(); ++i) {
        if (!bonded(i)) continue;
        const double ki = model.species[placed.species[i]].bondStiffness;
        cells.around(cells.cellOf(placed.pos[i]), 1, near);
        for (const auto& nb : near)
            for (std::uint32_t k = cells.start(nb.cell); k < cells.start(nb.cell + 1); ++k) {
                const std::uint32_t j = cells.order()[k];
                if (j == i || !bonded(j) || !bondedBags(bagParent, placed.species[i], placed.species[j])) continue;
                const double L = (placed.pos[j] - placed.pos[i]).norm();
                if (L >= reach || L == 0.0) continue;
                const double kj = model.species[placed.species[j]].bondStiffness;
                const double s = std::min(1.0, std::pow(r0 / L, 4));
                byId[placed.id[i]].push_back({placed.id[j], L, 2 * ki * kj / (ki + kj) * s});
            }
    }
    BondNetwork net;
    net.cut = cut;
    net.start.assign(idLimit + 1, 0);
    net.bulkVolume.assign(idLimit, 0.0);
    for (std::uint64_t id = 0; id < idLimit; ++id) {
        auto& list = byId[id];
        std::sort(list.begin(), list.end(), [](const Entry& a, const Entry& b) { return a.partner < b.partner; });
        for (const Entry& e : list) {
            net.partner.push_back(e.partner);
            net.rest.push_back(e.rest);
            net.stiffness.push_back(e.stiffness);
        }
        if (net.partner.size() >= std::numeric_limits<std::uint32_t>::max())
            throw std::runtime_error("bonds: more than 2^32 bond ends");
        net.start[id + 1] = std::uint32_t(net.partner.size());
    }
    traceCoefficients(placed, net);
    net.anchor.assign(idLimit, Eigen::Vector3d::Zero());
    net.anchorStiffness.assign(idLimit, 0.0);
    double lowest = std::numeric_limits<double>::infinity();
    for (std::uint32_t i = 0; i < placed.size(); ++i)
        if (bonded(i)) lowest = std::min(lowest, placed.pos[i].z());
    for (std::uint32_t i = 0; i < placed.size(); ++i) {
        if (!bonded(i)) continue;
        const Species& sp = model.species[placed.species[i]];
        net.bulkVolume[placed.id[i]] = sp.bondBulk * volume;
        net.anchor[placed.id[i]] = placed.pos[i];
        if (supportBelow > 0 && placed.pos[i].z() < lowest + supportBelow)
            net.anchorStiffness[placed.id[i]] = kAnchorBonds * sp.bondStiffness;
    }
    return net;
}

void BondForces::index(const BondNetwork& net, const Particles& p, const Halo* halo) {
    for (std::uint64_t id : filled_) where_[id] = -1;
    filled_.clear();
    where_.resize(net.idLimit(), -1);
    const auto put = [&](std::uint64_t id, std::int64_t at) {
        if (id >= net.idLimit()) return;
        where_[id] = at;
        filled_.push_back(id);
    };
    for (std::size_t i = 0; i < p.size(); ++i) put(p.id[i], std::int64_t(i));
    if (halo)
        for (std::size_t g = 0; g < halo->size(); ++g) put(halo->id[g], std::int64_t(p.size() + g));
}

void BondForces::dilatation(const BondNetwork& net, const Particles& p, const Halo* halo, std::vector<double>& theta) {
    index(net, p, halo);
    theta.assign(p.size(), 0.0);
    const auto posOf = [&](std::int64_t at) {
        return std::size_t(at) < p.size() ? p.pos[std::size_t(at)] : halo->pos[std::size_t(at) - p.size()];
    };
    const double cut2 = net.cut * net.cut;
    forEachIndex(p.size(), [&](std::size_t i) {
        const std::uint64_t id = p.id[i];
        if (id >= net.idLimit()) return;
        double s = 0;
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) {
            const std::int64_t at = where_[net.partner[b]];
            if (at < 0) continue;
            const double l2 = (posOf(at) - p.pos[i]).squaredNorm();
            if (l2 > cut2) continue;
            s += net.trace[b] * (std::sqrt(l2) - net.rest[b]);
        }
        theta[i] = s;
    });
}

double BondForces::add(const BondNetwork& net, Particles& p, const Halo* halo, const std::vector<double>& theta,
                       const std::vector<double>& ghostTheta, double& virial) {
    const auto posOf = [&](std::int64_t at) {
        return std::size_t(at) < p.size() ? p.pos[std::size_t(at)] : halo->pos[std::size_t(at) - p.size()];
    };
    const auto thetaOf = [&](std::int64_t at) {
        return std::size_t(at) < p.size() ? theta[std::size_t(at)] : ghostTheta[std::size_t(at) - p.size()];
    };
    const double cut2 = net.cut * net.cut;
    const std::array<double, 2> sums = sumsIndex<2>(p.size(), [&](std::size_t i) {
        const std::uint64_t id = p.id[i];
        if (id >= net.idLimit()) return std::array<double, 2>{};
        const double pressMine = net.bulkVolume[id] * theta[i];
        const Eigen::Vector3d held = net.anchor[id] - p.pos[i];  // a support's spring (0 without one)
        Eigen::Vector3d f = net.anchorStiffness[id] * held;
        double energy = 0.5 * (net.bulkVolume[id] * theta[i] * theta[i] + net.anchorStiffness[id] * held.squaredNorm());
        double w = 0;
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) {
            const std::uint64_t j = net.partner[b];
            const std::int64_t at = where_[j];
            if (at < 0) continue;
            const Eigen::Vector3d r = posOf(at) - p.pos[i];
            const double l2 = r.squaredNorm();
            if (l2 > cut2) continue;
            const double l = std::sqrt(l2), stretch = l - net.rest[b];
            const double tension = net.stiffness[b] * stretch + pressMine * net.trace[b] +
                                   net.bulkVolume[j] * thetaOf(at) * net.traceAtPartner[b];
            f += (tension / l) * r;
            energy += 0.25 * net.stiffness[b] * stretch * stretch;  // half of the bond's, at each end
            w -= 0.5 * tension * l;
        }
        p.force[i] += f;
        return std::array<double, 2>{energy, w};
    });
    virial += sums[1];
    return sums[0];
}

double segmentDistance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1) {
    const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
    constexpr double kTiny = 1e-300;
    double s = 0, t = 0;
    if (a <= kTiny && e <= kTiny) return r.norm();
    if (a <= kTiny) {
        t = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = d1.dot(r);
        if (e <= kTiny) {
            s = std::clamp(-c / a, 0.0, 1.0);
        } else {  // the closest points of the two lines, clamped to the segments
            const double b = d1.dot(d2), denom = a * e - b * b;
            s = denom > kTiny ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            t = (b * s + f) / e;
            if (t < 0) t = 0, s = std::clamp(-c / a, 0.0, 1.0);
            if (t > 1) t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
        }
    }
    return (p0 + d1 * s - (q0 + d2 * t)).norm();
}

BondNetwork breakBonds(const BondNetwork& net, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
                       std::size_t* broken) {
    BondNetwork out = net;
    std::size_t ends = 0;
    for (std::uint64_t id = 0; id < net.idLimit(); ++id)
        for (std::uint32_t b = net.start[id]; b < net.start[id + 1]; ++b) {
            if (net.stiffness[b] == 0 && net.trace[b] == 0) continue;  // broken before
            if (segmentDistance(net.anchor[id], net.anchor[net.partner[b]], from, to) > radius) continue;
            out.stiffness[b] = out.trace[b] = out.traceAtPartner[b] = 0;
            ++ends;
        }
    if (broken) *broken = ends / 2;
    return out;
}

}  // namespace bop::core
