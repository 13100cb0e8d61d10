// mpi.h as the host uses it: the C API alone (the deprecated C++ bindings need another library).
// Included by study/ranks.cpp and study/slab_ranks.cpp only; nothing without GDSMC_WITH_MPI.
#pragma once
#ifdef GDSMC_WITH_MPI
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif
