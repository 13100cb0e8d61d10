// `gdsmc conformance PLUGIN.so`: checks any plugin binary against the contract of its kind
// (loading, ABI, descriptor, parameter schema and validation, determinism, and the physics
// promised by collision rules, forcings, boundaries, initial states and diagnostics). Each check
// runs in its own process, so a plugin that crashes yields a CRASH line, not a dead runner.
#pragma once

namespace gdsmc::host {

// argv[0] is the command name ("conformance"); the rest are its arguments. Prints one line per
// check and returns 0 when every check passed or was skipped, 1 on any failure or crash, 2 for a
// bad command line.
int run_conformance(int argc, char** argv);

}  // namespace gdsmc::host
