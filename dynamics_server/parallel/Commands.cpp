#include "Commands.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

namespace bop::parallel {
namespace {

template <class Kind>
Command bodyAs(const CommandRecord& r) {
    Kind k;
    std::memcpy(static_cast<void*>(&k), r.body, sizeof k);
    return k;
}

template <std::size_t... I>
Command kindAt(const CommandRecord& r, std::index_sequence<I...>) {
    Command out;
    const bool known = ((r.kind == I ? (out = bodyAs<std::variant_alternative_t<I, Command>>(r), true) : false) || ...);
    if (!known)
        throw std::invalid_argument("command record: unknown command kind " + std::to_string(r.kind) +
                                    ", expected 0 to " + std::to_string(sizeof...(I) - 1));
    return out;
}

}  // namespace

CommandRecord recordOf(const Command& c) {
    CommandRecord r;
    r.kind = std::uint32_t(c.index());
    std::visit([&](const auto& k) { std::memcpy(r.body, static_cast<const void*>(&k), sizeof k); }, c);
    return r;
}

Command commandOf(const CommandRecord& r) {
    Command c = kindAt(r, std::make_index_sequence<std::variant_size_v<Command>>());
    if (const auto* w = std::get_if<core::WeightCommand>(&c); w && (int(w->table) < 0 || int(w->table) > 2))
        throw std::invalid_argument("command record: weight table " + std::to_string(int(w->table)) +
                                    ", expected 0 (LJ), 1 (co-normal) or 2 (co-planar)");
    return c;
}

}  // namespace bop::parallel
