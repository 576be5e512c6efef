#include "Params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::core {

Params::Params(const Model& scene) : lj(scene.lj), coNormal(scene.coNormal), coPlanar(scene.coPlanar) {
    drag.resize(scene.species.size());
    for (std::size_t s = 1; s < scene.species.size(); ++s) drag[s] = {scene.species[s].dragV, scene.species[s].dragW};
}

void Params::apply(const Command& c) {
    if (c.kind == Command::Kind::Probe) {
        probe = c.probe;
        return;
    }
    const int species = int(drag.size()) - 1;
    if (c.species < 1 || c.species > species)
        throw std::invalid_argument("command: no species " + std::to_string(c.species));
    if (c.kind == Command::Kind::Drag) {
        if (!(c.dragV >= 0 && c.dragW >= 0)) throw std::invalid_argument("drag command: drags must be 0 or more");
        drag[std::size_t(c.species)] = {c.dragV, c.dragW};
        return;
    }
    if (c.kind != Command::Kind::Weight) throw std::invalid_argument("command: not a probe, drag or weight command");
    if (c.other < 1 || c.other > species)
        throw std::invalid_argument("weight command: no species " + std::to_string(c.other));
    if (!std::isfinite(c.value) || c.value < 0)
        throw std::invalid_argument("weight command: weights must be 0 or more");
    WeightMatrix& w = c.table == Command::Table::Lj ? lj : c.table == Command::Table::CoNormal ? coNormal : coPlanar;
    w(c.species, c.other) = c.value;
}

}  // namespace bop::core
