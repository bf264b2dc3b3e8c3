// A scene script's runs under mpirun: the scene, built by the same script on
// every rank, stepped by a DistributedRun (distributed_run.hpp) and gathered
// whole onto every rank whenever the script can look at it (engine/spread_run.hpp).
#pragma once

#ifdef GRANULE_HAVE_MPI

#include <mpi.h>

#include "engine/spread_run.hpp"

namespace granule::parallel {

// Spread runs over the ranks of `comm`; `rebalance_threshold` as DistributedRun's.
SpreadRunMaker spread_over(MPI_Comm comm, double rebalance_threshold = 1.1);

}  // namespace granule::parallel

#endif  // GRANULE_HAVE_MPI
