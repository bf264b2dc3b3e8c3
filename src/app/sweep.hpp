// granule sweep SCENE.lua -D rpm=500,1000 -D gap=1.2e-3,1.6e-3 [-o DIR] [--threads N] [-q]
//               [--case-timeout SECONDS] [--list]
//
// Runs the Cartesian product of the listed parameter values, one `granule run`
// per case in a child process (a case that crashes takes only itself down),
// each writing DIR/<scene>_<name>=<value>_....h5 and a .log beside it. A case
// whose file carries the /sweep_case mark (io/case_record.hpp) is finished
// and skipped on a rerun. The summary DIR/<scene>.sweep.{csv,md,h5} lists
// every case with its values, status, rank, wall time and the scalars the
// scene reported with sim:result. Under mpirun the cases go to the ranks as
// they ask for work (rank 0 hands them out and runs cases too); built
// without MPI, or started without a launcher, they run in turn.
#pragma once

#include <string>
#include <vector>

namespace granule::app {

// args: everything after "sweep". Returns the exit status: 0 when every case
// finished, 1 when some failed, 2 for a bad command line, 128 + the signal after
// Ctrl-C (130) or SIGTERM (143).
int run_sweep(const std::vector<std::string>& args);

}  // namespace granule::app
