// The plugin search path and every plugin found on it (the first of a name wins), with the
// warnings about files that could not be used.
#pragma once
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "plugins/loader.hpp"

namespace gdsmc::host {

// Every plugin found on a search path; the first of a name wins.
class PluginRegistry {
 public:
  // Directories (scanned for *.so) or single .so files, in order of precedence.
  // Files named explicitly that fail to load are errors (thrown); files found by scanning a
  // directory that fail to load are kept as warnings.
  void add(const std::filesystem::path& dir_or_file);
  // The default search path: --plugin-path entries, then GDSMC_PLUGIN_PATH, then the plugins
  // directory beside the executable (build tree) or ../lib/gdsmc/plugins (installed).
  static std::vector<std::filesystem::path> default_search_path();

  const LoadedPlugin* find(const std::string& name) const;
  std::vector<std::string> names() const;
  std::vector<std::string> names_of_kind(PluginKind kind) const;
  const std::vector<LoadedPlugin>& plugins() const { return plugins_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  void add_file(const std::filesystem::path& file, bool explicit_file);
  std::vector<LoadedPlugin> plugins_;
  std::map<std::string, std::size_t> by_name_;
  std::vector<std::string> warnings_;
  std::vector<std::filesystem::path> seen_;
};

}  // namespace gdsmc::host
