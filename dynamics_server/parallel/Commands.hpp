#pragma once
// The record of a command (core/Command.hpp) that rank 0 broadcasts at the start of each step
// (MpiExchange::broadcast): the index of the command's kind, then the struct of that kind whole,
// as its bytes (core/Records.hpp), read back as a struct of that kind.
#include "core/Command.hpp"
#include "core/Records.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace bop::parallel {

using Command = core::Command;

namespace detail {
template <std::size_t... I>
constexpr std::size_t largestKind(std::index_sequence<I...>) {
    static_assert((core::kIsRecord<std::variant_alternative_t<I, Command>> && ...), "every kind is a record");
    return std::max({sizeof(std::variant_alternative_t<I, Command>)...});
}
}  // namespace detail

struct CommandRecord {
    static constexpr std::size_t kBodyBytes =
        detail::largestKind(std::make_index_sequence<std::variant_size_v<Command>>());
    std::uint32_t kind = 0;  // the index of the command's kind in core::Command
    alignas(16) std::byte body[kBodyBytes] = {};
};
static_assert(core::kIsRecord<CommandRecord>);

CommandRecord recordOf(const Command& c);
// std::invalid_argument naming the kind for a record of no known kind, or the table of a weight
// command of no known table.
Command commandOf(const CommandRecord& r);

}  // namespace bop::parallel
