// One PluginCallSite per plugin entry of a pipeline, for the fatal-signal handler
// (engine/plugin_calls.hpp): which plugin, in which role, from which line, at which step of which run.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "config/pipeline.hpp"
#include "engine/plugin_calls.hpp"

namespace gdsmc::host {

class CallSites {
 public:
  // Every entry of `p` (initial state, collision, forcings, the y boundaries, diagnostics); `step`
  // is the run's step counter, read when a call fails. Every text a site points to is built here.
  CallSites(const Pipeline& p, const std::uint64_t* step);
  CallSites(const CallSites&) = delete;  // the sites point into this object's texts
  CallSites& operator=(const CallSites&) = delete;
  // The site of an entry of the pipeline (an empty one for any other use).
  const PluginCallSite& of(const PluginUse& use) const;
  // This run's name ("run 2 of 4 (alpha=0.5)"; "" for a study of one run), for messages.
  const std::string& run_name() const { return run_name_; }

 private:
  std::string run_name_;
  std::vector<PluginCallSite> sites_;
  std::vector<const PluginUse*> uses_;
  std::vector<std::string> texts_;
};

}  // namespace gdsmc::host
