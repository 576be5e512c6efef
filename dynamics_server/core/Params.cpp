#include "Params.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace bop::core {

Params::Params(int species)
    : lj(species, 1.0), coNormal(species, 0.0), coPlanar(species, 0.0), drag(std::size_t(species) + 1) {}

void Params::apply(const Command& command) {
    const int species = int(drag.size()) - 1;
    const auto known = [&](int s, const char* what) {
        if (s < 1 || s > species)
            throw std::invalid_argument(std::string(what) + " command: no species " + std::to_string(s));
    };
    if (const auto* c = std::get_if<ProbeCommand>(&command)) {
        probe = c->probe;
    } else if (const auto* c = std::get_if<DragCommand>(&command)) {
        known(c->species, "drag");
        if (!(c->dragV >= 0 && c->dragW >= 0)) throw std::invalid_argument("drag command: drags must be 0 or more");
        drag[std::size_t(c->species)] = {c->dragV, c->dragW};
    } else if (const auto* c = std::get_if<WeightCommand>(&command)) {
        known(c->species, "weight");
        known(c->other, "weight");
        if (!std::isfinite(c->value) || c->value < 0)
            throw std::invalid_argument("weight command: weights must be 0 or more");
        WeightMatrix& w = c->table == WeightTable::Lj ? lj : c->table == WeightTable::CoNormal ? coNormal : coPlanar;
        w(c->species, c->other) = c->value;
    } else {
        throw std::invalid_argument("command: not a probe, drag or weight command");
    }
}

}  // namespace bop::core
