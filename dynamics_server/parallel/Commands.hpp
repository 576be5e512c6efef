#pragma once
// The message of commands (core/Command.hpp) that rank 0 broadcasts at the start of each step
// (MpiExchange::broadcast): one record per command, its kind first, then that kind's fields.
#include "core/Command.hpp"

#include <vector>

namespace bop::parallel {

using Command = core::Command;

// Flat form: per command [kind, then its fields]; decode() throws std::invalid_argument naming
// what is wrong with a malformed array.
void encode(const Command& c, std::vector<double>& out);
std::vector<Command> decode(const std::vector<double>& in);

}  // namespace bop::parallel
