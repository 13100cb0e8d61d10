// The help texts of `gdsmc run` and `gdsmc validate` (app/commands.hpp), beside the commands'
// own code in cmd_run.cpp.
#include "app/commands.hpp"

namespace gdsmc::host {

const char* const kRunHelp = R"(gdsmc run PIPELINE.yaml [options]

Runs the pipeline and writes one HDF5 file (the pipeline's output.file, default
<pipeline name>.h5 in the current directory). The output is checked before the first step: its
directory exists and is writable, the name is valid, and it is new, a regular file or a symbolic
link (the link is replaced, not its target), never an input of the run. A file it replaces is
named on stderr. The file is written under .FILE.gdsmc-partial-HOST-NS-PID-XXXXXX beside it and
renamed when complete: a failed or interrupted run (also during the final write) leaves nothing
under either name, and a run removes the temporaries of FILE left by killed runs of this host.
A failed write (disk full) exits 1 and says the results are lost.

Options:
  --set key.path=value   override a pipeline value before checking it, e.g.
                         --set collision.alpha=0.5  --set run.particles=20000
                         --set diagnostics[1].record_every=40 (lists by index)
                         --set boundaries.y_min.temperature=2
  -o, --output FILE      write to FILE instead of output.file
  -q, --quiet            no progress and no summary (errors are still printed)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --resume               continue from the checkpoint beside the output (<output>.checkpoint/)
  --decompose            under mpirun: each slab run is split over the ranks by layers (below)
  --threads N            threads; default run.threads, else every core; 1 is serial. Runs
                         (sweep cases x realizations) go at once, and threads left over work
                         inside each run (slab layers, sub-populations of a homogeneous system,
                         blocks of particles) when it is large enough to share (two or more
                         sub-populations; a slab of 16384 particles or more). The output is the
                         same bits for any N; memory
                         grows with the runs at once (each holds its particles)
  -h, --help             this text

With output.plots: true the finished file is then drawn by `gdsmc plot` (PNGs in
<output>_plots/); a plot that fails is a warning, not a failed run.

At the end the run prints what its diagnostics summarize, its energy balance, and where the
steps' wall time went ("time in the steps [s]: ... flight, sort, collisions, ..."; the same
seconds are in /run/stage_seconds.* of the file).

Checkpoints: with run.checkpoint in the pipeline, e.g.
    run: {checkpoint: {every: 30 min}}     (or {every: {collisions_per_particle: 50}}, or both
                                            in a list: {every: [30 min, {collisions_per_particle: 50}]})
every run writes its whole state into <output>.checkpoint/ at those intervals, at SIGINT/SIGTERM
(the step under way is finished first) and when it finishes; each write replaces the previous
one atomically, so a run killed at any moment (SIGKILL, a crash, a lost node) loses at most one
interval. `gdsmc run PIPELINE.yaml --resume` (same --set and -o) continues every unfinished run
where its state was saved and gives the output of the uninterrupted run, to the bit; run.threads
and run.checkpoint may change, nothing else: a checkpoint of another pipeline text, another gdsmc
or plugin version, or plugin library content (a 64-bit hash of each .so) is refused with what
differs. Every entry of a checkpoint carries a checksum, checked before anything runs: a damaged
file is refused naming it. --resume says "finished" (exit 0) when the output of this pipeline is
complete, "nothing to resume" when there is no checkpoint, "damaged" naming the file. The
directory is removed once the output is written; a fresh run refuses to start over an existing
one. A state holds every particle (about N x 28 bytes homogeneous, N x 60 slab, per run under way).

Progress (s, t/tau0, T/T0, time left) goes to stderr: one refreshed line on a terminal,
a plain line every 10 s otherwise. The summary after the run goes to stdout.

Before anything runs, the pipeline is checked as `validate` checks it (and what validate says
about the numbers as read goes to stderr, unless --quiet), the memory the study needs
is estimated and the run is refused when it cannot fit in the memory available (see validate).

MPI (a host built with it: `gdsmc --version`): `mpirun -np K gdsmc run PIPELINE.yaml` (or srun)
spreads the runs over K ranks, each with --threads threads (default: its share of its node's
cores), balanced by expected cost (particles x steps); rank 0 gathers every run and writes the
file: the same bits as --threads 1 without MPI. Progress and the summary are printed once; a run
that fails on any rank ends the job with its message and exit 1, nothing written; a rank that
dies (killed by a signal, crashed) is named with its runs, nothing written either; checkpoints
are shared, and resume at any number of ranks. See docs/cluster.md.

One slab over ranks: `mpirun -np K gdsmc run PIPELINE.yaml --decompose` splits each run's layers
into K contiguous blocks, one per rank (threads inside each), in turn for every run of the study.
Particles move between ranks after each flight; block boundaries follow the measured cost of the
layers (particles and collision candidates) every 16 steps. The output is the same bits as the
single-process run at any K, thread count and block boundaries. Diagnostics that read no particle
(SDK 6.6: profiles, poiseuille_channel, slab_averages, temperature, ...) sample from sums the ranks
share; rank 0 gathers the particles for the samples of the others, for forcings that act on the
particles, for checkpoints and at the end, and holds every particle then (about N x 64 bytes). Checkpoints resume at any K, with or without
--decompose. Not decomposed (refused, by name): homogeneous systems (one collision cell), more
ranks than layers, plugins that declare per-particle attributes. A failure on any rank
ends the job (MPI_Abort) with that rank's message. See docs/scaling.md.
)";

const char* const kValidateHelp = R"(gdsmc validate PIPELINE.yaml [options]

Checks the pipeline without running it: YAML syntax, every key, every plugin and parameter
(type, range, unit), and that every plugin accepts its parameters and sets up (every plugin
object is constructed and every diagnostic begins; no particles are allocated and the initial
state is not generated, so a large N is checked as quickly as a small one). Every problem is
reported with file:line:column. The output file is checked as `run` checks it (a temporary file
is created beside it and removed at once; an existing file a run would replace is named).
Exit 0 when valid, 1 otherwise. Plugin files on the search path that could not be loaded (and
are therefore shadowed or missing) are reported as warnings.

Before the verdict it prints every dimensional value written as a bare number, what it was read
as (a length in lambda0, a time in tau0, ...) and its value in the other common units, then the
dimensionless numbers of each case (n sigma^3 and phi, Kn = lambda0/Ly and particles per layer
of a slab, dt over the mean free time) and those its diagnostics state as they begin (a_hat,
epsilon_star, ...). `units: explicit` in the pipeline makes a bare dimensional number an error.

The verdict gives the memory the study is estimated to need (particles, attributes, every
diagnostic's records, what each sweep case keeps until the file is written); a study that needs
more than is available (the smaller of MemAvailable and what ulimit -v / -d leave) is refused
with both figures. The pipeline file must be a regular file of at most 16 MiB. Checking a sweep
that takes more than 2 s prints its progress on stderr every 2 s.

Options (those of `run`, so that a run's command line can be checked by changing the command):
  --set key.path=value   override a pipeline value before checking it (repeatable)
  -o, --output FILE      the output file to check (nothing is left behind)
  -q, --quiet            as for run: no progress lines (validate prints its verdict and problems)
  --plugin-path P        a plugin directory or .so file searched first (repeatable)
  --threads N            as for run: the runs at once that the memory estimate assumes
  --resume               also check that the checkpoint beside the output belongs to this
                         pipeline, gdsmc and plugins, and read every file of it as run --resume
                         would (checksums, each run's state); say how many runs it holds
  --decompose            also refuse what `run --decompose` would not split over the ranks
                         (a homogeneous system, more ranks than layers)
  -h, --help             this text
)";

}  // namespace gdsmc::host
