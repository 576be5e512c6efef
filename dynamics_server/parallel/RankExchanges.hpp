#pragma once
// The exchanges of a run over MPI_COMM_WORLD's ranks, for core::Run (no <mpi.h> here): one
// Cartesian rank grid for the run, made at its start, and an MpiExchange over it at every start
// and reseat.
#include "core/Run.hpp"

namespace bop::parallel {

core::ExchangeMaker rankExchanges();

}  // namespace bop::parallel
