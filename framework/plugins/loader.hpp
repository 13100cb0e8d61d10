// Loading and checking one plugin binary (Boost.DLL): the single implementation of the entry,
// ABI and fingerprint checks (the registry and `gdsmc conformance` both use it), and making
// objects that keep their library loaded.
#pragma once
#include <filesystem>
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

// The steps of load_plugin, each throwing PluginLoadError with a message that starts with the file.
// Open the library with every symbol resolved (rtld_now) and no symbol leaking to other plugins.
std::shared_ptr<boost::dll::shared_library> open_library(const std::filesystem::path& file);
// The library's plugin entry (exported symbol present, entry returned, magic number right).
const PluginEntry& plugin_entry(boost::dll::shared_library& lib, const std::filesystem::path& file);

// Whether an entry's ABI fits this host: `problem` is empty when it does.
struct AbiCheck {
  std::string versions;  // "plugin SDK ABI a.b, host SDK ABI c.d"
  std::string problem;   // what is wrong, e.g. "built against an incompatible gdsmc SDK"
  std::string remedy;    // what to do about it
};
AbiCheck check_abi(const PluginEntry& entry);

// Make an object with the plugin's factory. The returned pointer owns a reference to the library,
// so the library outlives every object made from it.
std::shared_ptr<PluginObject> create_object(const LoadedPlugin& plugin, const Params& params);

}  // namespace gdsmc::host
