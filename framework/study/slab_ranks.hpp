// The ranks of an MPI job as one decomposed slab run's (`gdsmc run --decompose`,
// engine/decomposition.hpp): the collectives over MPI_COMM_WORLD. Only slab_ranks.cpp and
// ranks.cpp include mpi.h. A job of one process (no launcher, or a host built without MPI) is a
// decomposition over one rank: every collective is then the identity.
#pragma once
#include <memory>

#include "engine/decomposition.hpp"

namespace gdsmc::host::job {

// The ranks of this job (job::Session must be alive). Main thread only (MPI_THREAD_FUNNELED).
std::unique_ptr<Decomposition> slab_ranks();

// Ends every rank of the job with `status` (MPI_Abort), after removing this rank's temporary output
// file and lock (rank 0's): a decomposed run whose rank failed cannot go on, and the other ranks
// would wait for it in their next collective. Without MPI: exit(status).
[[noreturn]] void abort_job(int status);

}  // namespace gdsmc::host::job
