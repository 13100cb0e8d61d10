// The plugin search path and every plugin found on it (the first of a name wins), with the
// warnings about files that could not be used.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "plugins/loader.hpp"

namespace gdsmc::host {

// Every plugin found on a search path; the first of a name wins. Every library is examined
// without being loaded here (examine_libraries); a plugin is loaded here when it is first used
// (find, plugins), so a library the pipeline does not use never runs in this process. Not for
// concurrent use (const lookups may load).
class PluginRegistry {
 public:
  // Directories (scanned for *.so) or single .so files, in order of precedence.
  // Files named explicitly that fail to load are errors (thrown); files found by scanning a
  // directory that fail to load are kept as warnings.
  void add(const std::filesystem::path& dir_or_file);
  // The default search path: --plugin-path entries, then GDSMC_PLUGIN_PATH, then the plugins
  // directory beside the executable (build tree) or ../lib/gdsmc/plugins (installed).
  static std::vector<std::filesystem::path> default_search_path();

  // The plugin of that name, loaded (nullptr if there is none). Throws PluginLoadError if it
  // cannot be loaded after all (its file changed since it was examined).
  const LoadedPlugin* find(const std::string& name) const;
  std::vector<std::string> names() const;
  std::vector<std::string> names_of_kind(PluginKind kind) const;
  // Every plugin found, as examined (nothing is loaded).
  const std::vector<PluginInfo>& available() const { return found_; }
  // Every plugin found, all of them loaded.
  const std::vector<LoadedPlugin>& plugins() const;
  const std::vector<std::string>& warnings() const { return warnings_; }
  // The directories and files given to add(), in order (what a lookup searched).
  const std::vector<std::filesystem::path>& searched() const { return searched_; }

 private:
  // Examine the files not seen before (one probe process for all of them) and keep the plugins.
  void add_files(const std::vector<std::filesystem::path>& files, bool explicit_file);
  const LoadedPlugin& loaded(std::size_t k) const;
  std::vector<PluginInfo> found_;
  mutable std::vector<LoadedPlugin> plugins_;  // beside found_; empty (no descriptor) until loaded
  std::map<std::string, std::size_t> by_name_;
  std::vector<std::string> warnings_;
  std::vector<std::filesystem::path> seen_;
  std::vector<std::filesystem::path> searched_;
};

}  // namespace gdsmc::host
