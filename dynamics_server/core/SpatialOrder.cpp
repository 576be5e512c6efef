#include "SpatialOrder.hpp"

#include "CellList.hpp"
#include "Threads.hpp"

#include <stdexcept>
#include <string>

namespace bop::core {

std::vector<std::uint32_t> spatialOrder(const Box& box, double cell, const std::vector<Eigen::Vector3d>& pos,
                                        const std::vector<std::uint64_t>& id) {
    if (!(cell > 0)) throw std::invalid_argument("spatialOrder: the cell width must be positive");
    Box cut = box;
    cut.periodic = {false, false, false};  // particles wrapped or not: the same cells
    CellList cells;
    cells.build(cut, cell, pos, &id);
    return cells.order();
}

namespace {

template <class T>
void permute(std::vector<T>& v, const std::vector<std::uint32_t>& order) {
    std::vector<T> out(v.size());
    forEachIndex(v.size(), [&](std::size_t k) { out[k] = v[order[k]]; });
    v.swap(out);
}

}  // namespace

void reorder(Particles& p, const std::vector<std::uint32_t>& order) {
    if (order.size() != p.size())
        throw std::invalid_argument("reorder: an order of " + std::to_string(order.size()) + " for " +
                                    std::to_string(p.size()) + " particles");
    permute(p.pos, order);
    permute(p.vel, order);
    permute(p.q, order);
    permute(p.omega, order);
    permute(p.normal, order);
    permute(p.force, order);
    permute(p.torque, order);
    permute(p.species, order);
    permute(p.id, order);
    ++p.revision;
}

}  // namespace bop::core
