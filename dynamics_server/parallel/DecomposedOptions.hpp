#pragma once
// What a decomposed run starts from besides the model and the particles (no <mpi.h> here, so
// tools outside parallel/ can fill it in): a run's options (core/Simulation.hpp).
#include "core/Simulation.hpp"

namespace bop::parallel {

using MapSource = core::MapSource;
using DecomposedOptions = core::SimulationOptions;

}  // namespace bop::parallel
