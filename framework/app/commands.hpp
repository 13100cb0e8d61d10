// The subcommands of the gdsmc executable (main.cpp dispatches to them) and their help texts.
#pragma once
#include <string>
#include <vector>

#include "app/cli.hpp"

namespace gdsmc::host {

extern const char* const kRunHelp;
extern const char* const kValidateHelp;
extern const char* const kPluginsHelp;

// `run` (run_it) or `validate`. Returns the exit status.
int cmd_run(const Options& o, bool run_it);
// `plugins`: list, or document the plugins named.
int cmd_plugins(const Options& o);

// "gdsmc: message" and a pointer to --help on stderr; returns 2.
int usage_error(const std::string& message);
// Every message as "error: ..." and a count on stderr.
void print_errors(const std::vector<std::string>& messages);
// Every message as "warning: ..." on stderr.
void print_warnings(const std::vector<std::string>& messages);

}  // namespace gdsmc::host
