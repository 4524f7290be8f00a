#pragma once
// clothsim batch across MPI ranks (built when CMake finds MPI; docs/batch.md): rank 0 hands the scenes out one
// at a time as ranks free up and gathers the results; every other rank runs the scenes it is given, each as a
// child process exactly as a local batch does. Outputs go to the shared --out folder.
#include <functional>
#include <vector>

#include "tools/batch_list.h"

namespace clothsim::cli {

// True when this process was started by an MPI launcher (mpirun, srun) with more than one rank and clothsim
// was built with MPI. Initialises MPI then; batch_mpi_finalize ends it.
bool batch_mpi_start(int& rank);
void batch_mpi_finalize();

// Rank 0: hands out `queue` (indices into `scenes`), fills in each scene's result from the worker that ran it
// and calls on_done for it. Other ranks: run what they are given; `scenes` is left as it was.
void batch_mpi_run(std::vector<BatchScene>& scenes, const std::vector<std::size_t>& queue, int threads,
                   int checkpoint_every, const std::function<void(const BatchScene&)>& on_done);

}  // namespace clothsim::cli
