// Helpers shared by the gdsmc tests, one header per purpose under tests/support/: where things are,
// temporary directories and text (files.hpp), the executable as a child process (process.hpp), a
// pipeline it must refuse (refusal.hpp), HDF5 files read back (hdf5.hpp), small pipelines and the
// host in-process (pipelines.hpp), and numerics (numerics.hpp). The child processes and the HDF5
// reading are the host's own (framework/util/subprocess.hpp, framework/output/hdf5_reader.hpp).
#pragma once
// The POSIX headers the tests use beside the helpers (signals, fork and wait, file descriptors).
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "support/files.hpp"
#include "support/hdf5.hpp"
#include "support/numerics.hpp"
#include "support/pipelines.hpp"
#include "support/process.hpp"
#include "support/refusal.hpp"
