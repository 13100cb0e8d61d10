// Finding, loading and checking plugin binaries (Boost.DLL), and making objects that keep their
// library loaded.
#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gdsmc/plugin.hpp>

namespace boost::dll {
class shared_library;
}

namespace gdsmc::host {

// Thrown when a file cannot be used as a plugin; the message names the file and what to do.
class PluginLoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct LoadedPlugin {
  std::filesystem::path file;
  std::shared_ptr<boost::dll::shared_library> library;
  const PluginDescriptor* descriptor = nullptr;
  std::uint32_t abi_major = 0, abi_minor = 0;
};

// Load one shared library and check it is a gdsmc plugin of a compatible ABI.
LoadedPlugin load_plugin(const std::filesystem::path& file);

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

// Make an object with the plugin's factory. The returned pointer owns a reference to the library,
// so the library outlives every object made from it.
std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params);

}  // namespace gdsmc::host
